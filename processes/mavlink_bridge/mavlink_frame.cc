#include "processes/mavlink_bridge/mavlink_frame.h"

#include <algorithm>
#include <cmath>

namespace nadir::mavlink {
namespace {

constexpr size_t kHeaderV1 = 6;
constexpr size_t kHeaderV2 = 10;
constexpr size_t kCrcLength = 2;
// Unknown frames in a row that may confirm each other before a known frame
// (or the end of a datagram) must: longer runs are taken for garbage.
constexpr int kMaxUnknownChain = 64;

bool is_start(uint8_t byte, bool accept_v1) { return byte == kStxV2 || (accept_v1 && byte == kStxV1); }

}  // namespace

void FrameParser::feed(const uint8_t* data, size_t size, int64_t arrival_us, double byte_time_us,
                       std::vector<Frame>* out) {
  counts_.bytes += static_cast<int64_t>(size);
  for (size_t i = 0; i < size; ++i) {
    buffer_.push_back(data[i]);
    arrival_.push_back(arrival_us + std::llround(static_cast<double>(i) * byte_time_us));
  }
  process(false, out);
}

void FrameParser::end_of_datagram(std::vector<Frame>* out) {
  process(true, out);
  close_span();
}

void FrameParser::reset() {
  // Only an unfinished candidate can be left: its rest is not coming.
  if (!buffer_.empty()) {
    reject_candidate(&counts_.truncated, "link reopened inside a frame");
    reject_bytes(buffer_.size());
  }
  close_span();
}

void FrameParser::process(bool at_end, std::vector<Frame>* out) {
  while (!buffer_.empty()) {
    if (!is_start(buffer_[0], options_.accept_v1)) {
      size_t k = 1;
      while (k < buffer_.size() && !is_start(buffer_[k], options_.accept_v1)) ++k;
      reject_bytes(k);
      continue;
    }
    Frame frame;
    size_t frame_size = 0;
    Verdict verdict = examine(at_end, &frame, &frame_size);
    if (verdict == Verdict::kNeedMore) {
      if (!at_end) break;
      // The bytes it needs will not come; the bytes after its start byte may
      // still hold whole frames.
      reject_candidate(&counts_.truncated, "input ended inside a frame");
      verdict = Verdict::kRejected;
    }
    if (verdict == Verdict::kRejected) {
      reject_bytes(1);
      continue;
    }
    if (verdict == Verdict::kAccepted) {
      close_span();
      frame.start_arrival_us = arrival_[0];
      out->push_back(frame);
    }
    drop_bytes(frame_size);
  }
}

FrameParser::Candidate FrameParser::inspect(size_t pos, bool at_end, int depth) const {
  Candidate c;
  const size_t avail = buffer_.size() - pos;
  const uint8_t* p = buffer_.data() + pos;
  const bool v2 = p[0] == kStxV2;
  const size_t header = v2 ? kHeaderV2 : kHeaderV1;
  if (avail < header) return c;  // kNeedMore
  c.v2 = v2;
  c.length = p[1];
  auto reject = [&c](int64_t FrameCounts::*counter, const char* reason) {
    c.verdict = Verdict::kRejected;
    c.counter = counter;
    c.reason = reason;
    return c;
  };
  bool is_signed = false;
  if (v2) {
    if (p[2] & ~kIncompatSigned) return reject(&FrameCounts::bad_flags, "incompatibility flags not supported");
    is_signed = (p[2] & kIncompatSigned) != 0;
    c.msgid = static_cast<uint32_t>(p[7]) | (static_cast<uint32_t>(p[8]) << 8) | (static_cast<uint32_t>(p[9]) << 16);
  } else {
    c.msgid = p[5];
  }
  const size_t total = header + c.length + kCrcLength + (is_signed ? kSignatureLength : 0);
  const MessageInfo* info = find_message(c.msgid);
  if (!info) {
    if (!options_.skip_unknown) return reject(&FrameCounts::unknown_id, "unknown");
    // Its CRC cannot be checked, so it is skipped whole only when what
    // follows confirms where it ends: the end of the input, or a frame that
    // checks out (a known one with a good CRC, or unknown ones confirmed so).
    if (avail < total || (avail == total && !at_end)) return c;
    if (avail > total) {
      if (depth >= kMaxUnknownChain) return reject(&FrameCounts::unknown_id, "unknown, too many in a row");
      if (!is_start(p[total], options_.accept_v1)) return reject(&FrameCounts::unknown_id, "unknown, no frame follows");
      const Candidate next = inspect(pos + total, at_end, depth + 1);
      if (next.verdict == Verdict::kNeedMore && !at_end) return c;
      if (next.verdict != Verdict::kAccepted && next.verdict != Verdict::kSkippedUnknown) {
        return reject(&FrameCounts::unknown_id, "unknown, the frame after it is bad");
      }
    }
    // Nor may it swallow a frame that checks out (garbage before a good frame
    // must not be taken for an unknown frame spanning it).
    for (size_t i = pos + 1; i < pos + total; ++i) {
      if (is_start(buffer_[i], options_.accept_v1) &&
          inspect(i, at_end, kMaxUnknownChain).verdict == Verdict::kAccepted) {
        return reject(&FrameCounts::unknown_id, "unknown, a good frame starts inside it");
      }
    }
    c.verdict = Verdict::kSkippedUnknown;
    c.size = total;
    return c;
  }
  const bool length_ok = v2 ? c.length <= info->length : (c.length >= info->base_length && c.length <= info->length);
  if (!length_ok) return reject(&FrameCounts::bad_length, "length impossible for the message");
  if (avail < total) return c;
  uint16_t crc = crc_accumulate(p + 1, header - 1 + c.length, kCrcSeed);
  crc = crc_accumulate(info->crc_extra, crc);
  const uint16_t sent = static_cast<uint16_t>(p[header + c.length] | (p[header + c.length + 1] << 8));
  if (crc != sent) return reject(&FrameCounts::bad_crc, "CRC mismatch");
  c.verdict = Verdict::kAccepted;
  c.size = total;
  return c;
}

FrameParser::Verdict FrameParser::examine(bool at_end, Frame* frame, size_t* frame_size) {
  const Candidate c = inspect(0, at_end, 0);
  if (c.verdict == Verdict::kRejected) {
    const MessageInfo* info = find_message(c.msgid);
    reject_candidate(&(counts_.*c.counter), std::string(c.v2 ? "v2 " : "v1 ") +
                                                (info ? info->name : "message id " + std::to_string(c.msgid)) +
                                                " (" + std::to_string(c.length) + " payload bytes): " + c.reason);
    return c.verdict;
  }
  if (c.verdict == Verdict::kNeedMore) return c.verdict;
  *frame_size = c.size;
  if (c.verdict == Verdict::kSkippedUnknown) {
    ++counts_.unknown_skipped;
    return c.verdict;
  }
  const uint8_t* p = buffer_.data();
  const bool v2 = p[0] == kStxV2;
  const size_t header = v2 ? kHeaderV2 : kHeaderV1;
  frame->version = v2 ? 2 : 1;
  frame->seq = v2 ? p[4] : p[2];
  frame->sysid = v2 ? p[5] : p[3];
  frame->compid = v2 ? p[6] : p[4];
  frame->msgid = v2 ? (static_cast<uint32_t>(p[7]) | (static_cast<uint32_t>(p[8]) << 8) |
                       (static_cast<uint32_t>(p[9]) << 16))
                    : p[5];
  frame->payload_length = p[1];
  frame->payload.fill(0);
  std::copy(p + header, p + header + p[1], frame->payload.begin());
  frame->is_signed = v2 && (p[2] & kIncompatSigned);
  if (v2) ++counts_.frames_v2;
  else ++counts_.frames_v1;
  if (frame->is_signed) ++counts_.frames_signed;
  return Verdict::kAccepted;
}

void FrameParser::reject_candidate(int64_t* counter, const std::string& why) {
  ++*counter;
  last_error_ = "byte " + std::to_string(counts_.bytes - static_cast<int64_t>(buffer_.size())) + ": " + why;
}

void FrameParser::drop_bytes(size_t count) {
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(count));
  arrival_.erase(arrival_.begin(), arrival_.begin() + static_cast<std::ptrdiff_t>(count));
}

void FrameParser::reject_bytes(size_t count) {
  drop_bytes(count);
  span_open_ = true;
  counts_.garbage_bytes += static_cast<int64_t>(count);
}

void FrameParser::close_span() {
  if (!span_open_) return;
  ++counts_.rejected_spans;
  span_open_ = false;
}

std::vector<uint8_t> FrameEncoder::encode_raw(uint32_t msgid, uint8_t crc_extra, const std::vector<uint8_t>& payload,
                                              size_t base_length, int version) {
  std::vector<uint8_t> out;
  if (version == 1) {
    const size_t length = std::min(base_length, payload.size());
    out = {kStxV1, static_cast<uint8_t>(length), seq_, sysid_, compid_, static_cast<uint8_t>(msgid)};
    out.insert(out.end(), payload.begin(), payload.begin() + static_cast<std::ptrdiff_t>(length));
  } else {
    size_t length = payload.size();
    while (length > 1 && payload[length - 1] == 0) --length;
    out = {kStxV2, static_cast<uint8_t>(length), 0, 0, seq_, sysid_, compid_, static_cast<uint8_t>(msgid),
           static_cast<uint8_t>(msgid >> 8), static_cast<uint8_t>(msgid >> 16)};
    out.insert(out.end(), payload.begin(), payload.begin() + static_cast<std::ptrdiff_t>(length));
  }
  uint16_t crc = crc_accumulate(out.data() + 1, out.size() - 1, kCrcSeed);
  crc = crc_accumulate(crc_extra, crc);
  out.push_back(static_cast<uint8_t>(crc));
  out.push_back(static_cast<uint8_t>(crc >> 8));
  ++seq_;
  return out;
}

}  // namespace nadir::mavlink
