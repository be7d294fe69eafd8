#include "processes/mavlink_bridge/mavlink_frame.h"

#include <algorithm>
#include <cmath>

namespace nadir::mavlink {
namespace {

constexpr size_t kHeaderV1 = 6;
constexpr size_t kHeaderV2 = 10;
constexpr size_t kCrcLength = 2;

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
  std::vector<Frame> ignored;  // a reopened link: even whole frames left are stale
  process(true, &ignored);
  span_open_ = false;
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

FrameParser::Verdict FrameParser::examine(bool at_end, Frame* frame, size_t* frame_size) {
  const size_t avail = buffer_.size();
  const uint8_t* p = buffer_.data();
  const bool v2 = p[0] == kStxV2;
  const size_t header = v2 ? kHeaderV2 : kHeaderV1;
  if (avail < header) return Verdict::kNeedMore;
  const uint8_t length = p[1];
  bool is_signed = false;
  uint32_t msgid = 0;
  if (v2) {
    const uint8_t incompat = p[2];
    if (incompat & ~kIncompatSigned) {
      reject_candidate(&counts_.bad_flags, "incompatibility flags 0x" + std::to_string(incompat) + " not supported");
      return Verdict::kRejected;
    }
    is_signed = (incompat & kIncompatSigned) != 0;
    msgid = static_cast<uint32_t>(p[7]) | (static_cast<uint32_t>(p[8]) << 8) | (static_cast<uint32_t>(p[9]) << 16);
  } else {
    msgid = p[5];
  }
  const size_t total = header + length + kCrcLength + (is_signed ? kSignatureLength : 0);
  const MessageInfo* info = find_message(msgid);
  if (!info) {
    if (!options_.skip_unknown) {
      reject_candidate(&counts_.unknown_id, "message id " + std::to_string(msgid) + " unknown");
      return Verdict::kRejected;
    }
    // Its CRC cannot be checked: only a frame that ends where another starts is skipped whole.
    if (avail < total || (avail == total && !at_end)) return Verdict::kNeedMore;
    if (avail > total && !is_start(p[total], options_.accept_v1)) {
      reject_candidate(&counts_.unknown_id, "message id " + std::to_string(msgid) + " unknown, no frame follows");
      return Verdict::kRejected;
    }
    ++counts_.unknown_skipped;
    *frame_size = total;
    return Verdict::kSkippedUnknown;
  }
  const bool length_ok = v2 ? length <= info->length : (length >= info->base_length && length <= info->length);
  if (!length_ok) {
    reject_candidate(&counts_.bad_length, std::string(info->name) + " with " + std::to_string(length) +
                                              " payload bytes (v" + (v2 ? "2" : "1") + ")");
    return Verdict::kRejected;
  }
  if (avail < total) return Verdict::kNeedMore;
  uint16_t crc = crc_accumulate(p + 1, header - 1 + length, kCrcSeed);
  crc = crc_accumulate(info->crc_extra, crc);
  const uint16_t sent = static_cast<uint16_t>(p[header + length] | (p[header + length + 1] << 8));
  if (crc != sent) {
    reject_candidate(&counts_.bad_crc, std::string(info->name) + ": CRC mismatch");
    return Verdict::kRejected;
  }
  frame->version = v2 ? 2 : 1;
  frame->seq = v2 ? p[4] : p[2];
  frame->sysid = v2 ? p[5] : p[3];
  frame->compid = v2 ? p[6] : p[4];
  frame->msgid = msgid;
  frame->payload_length = length;
  frame->payload.fill(0);
  std::copy(p + header, p + header + length, frame->payload.begin());
  frame->is_signed = is_signed;
  if (v2) ++counts_.frames_v2;
  else ++counts_.frames_v1;
  if (is_signed) ++counts_.frames_signed;
  *frame_size = total;
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
