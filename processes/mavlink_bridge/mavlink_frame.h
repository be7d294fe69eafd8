#pragma once
// MAVLink framing: v2 frames (0xFD) written and read, v1 frames (0xFE) read.
// A frame is accepted only when its id is known, its length fits the message
// (v1: at least the base fields; v2: up to the full length, trailing zeros
// truncated) and its
// CRC with the message's CRC_EXTRA matches. Signed v2 frames are accepted
// with the signature skipped, not verified (signing is not configured).
//
// The parser never trusts a candidate's declared length to skip bytes it has
// not verified: a rejected candidate gives up one byte and the search resumes
// after its start byte, so a corrupt header cannot hide the good frame behind
// it. Frames with an unknown id are skipped whole (when skip_unknown) only
// when what follows confirms where they end (the end of the input, or a frame
// that checks out) and no frame that checks out starts inside them.
//
// Accounting: every byte fed ends up in an accepted frame, a skipped unknown
// frame, or a rejected span; a rejected span is one maximal run of bytes
// between accepted frames that decoded to nothing and is counted once, when
// it closes (at the next accepted frame, at end_of_datagram(), or reset()).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "processes/mavlink_bridge/mavlink_codec.h"

namespace nadir::mavlink {

inline constexpr uint8_t kStxV1 = 0xFE;
inline constexpr uint8_t kStxV2 = 0xFD;
inline constexpr uint8_t kIncompatSigned = 0x01;
inline constexpr size_t kSignatureLength = 13;

struct Frame {
  int version = 2;
  uint8_t seq = 0;
  uint8_t sysid = 0;
  uint8_t compid = 0;
  uint32_t msgid = 0;
  uint8_t payload_length = 0;
  std::array<uint8_t, kMaxPayload> payload{};
  bool is_signed = false;
  int64_t start_arrival_us = 0;  // arrival time of the start byte

  template <class M>
  M decode() const {
    return decode_payload<M>(payload.data(), payload_length);
  }
};

struct FrameCounts {
  int64_t bytes = 0;
  int64_t frames_v1 = 0;
  int64_t frames_v2 = 0;
  int64_t frames_signed = 0;      // accepted, signature not verified
  int64_t unknown_skipped = 0;    // well-formed frames of ids nadir does not read
  int64_t rejected_spans = 0;     // runs of bytes that decoded to nothing
  int64_t garbage_bytes = 0;      // bytes in those runs
  // Why candidates (a start byte and what followed) were rejected; one span
  // may hold several.
  int64_t bad_crc = 0;
  int64_t bad_length = 0;         // length not possible for the message
  int64_t bad_flags = 0;          // incompatibility flags nadir does not support
  int64_t unknown_id = 0;         // id unknown and the frame's end not confirmed
  int64_t truncated = 0;          // input ended (datagram, reset) inside a frame
  int64_t accepted() const { return frames_v1 + frames_v2; }
};

struct FrameParserOptions {
  bool skip_unknown = true;  // false: an unknown id is a bad candidate (strict, for fuzzing)
  bool accept_v1 = true;
};

class FrameParser {
 public:
  explicit FrameParser(FrameParserOptions options = {}) : options_(options) {}

  // Appends bytes (arrived at arrival_us, each byte_time_us after the last)
  // and returns the frames completed by them.
  void feed(const uint8_t* data, size_t size, int64_t arrival_us, double byte_time_us, std::vector<Frame>* out);
  // UDP: a frame never continues in the next datagram. Whole frames behind a
  // candidate cut off by the end are still returned.
  void end_of_datagram(std::vector<Frame>* out);
  // The link was reopened: what is buffered is dropped (counted truncated).
  void reset();

  const FrameCounts& counts() const { return counts_; }
  const std::string& last_error() const { return last_error_; }

 private:
  enum class Verdict { kAccepted, kSkippedUnknown, kRejected, kNeedMore };
  struct Candidate {
    Verdict verdict = Verdict::kNeedMore;
    size_t size = 0;                          // bytes of an accepted or skipped frame
    int64_t FrameCounts::*counter = nullptr;  // rejected: which count, and why
    const char* reason = "";
    bool v2 = true;
    uint32_t msgid = 0;
    uint8_t length = 0;
  };
  void process(bool at_end, std::vector<Frame>* out);
  // The candidate starting at `pos`, without changing anything.
  Candidate inspect(size_t pos, bool at_end, int depth) const;
  // The candidate at the buffer's start; at_end: no more bytes will follow.
  Verdict examine(bool at_end, Frame* frame, size_t* frame_size);
  void reject_candidate(int64_t* counter, const std::string& why);
  void reject_bytes(size_t count);
  void drop_bytes(size_t count);
  void close_span();

  FrameParserOptions options_;
  std::vector<uint8_t> buffer_;
  std::vector<int64_t> arrival_;  // per buffered byte
  bool span_open_ = false;
  FrameCounts counts_;
  std::string last_error_;
};

// Frame writer: v2 (zeros truncated, at least one payload byte) or v1 (base
// fields only; ids above 255 cannot be sent as v1).
class FrameEncoder {
 public:
  FrameEncoder(uint8_t sysid, uint8_t compid) : sysid_(sysid), compid_(compid) {}

  template <class M>
  std::vector<uint8_t> encode(const M& msg, int version = 2) {
    const std::vector<uint8_t> payload = encode_payload(msg);
    return encode_raw(M::kId, M::kCrcExtra, payload, message_info<M>().base_length, version);
  }
  std::vector<uint8_t> encode_raw(uint32_t msgid, uint8_t crc_extra, const std::vector<uint8_t>& payload,
                                  size_t base_length, int version);
  uint8_t next_seq() const { return seq_; }

 private:
  uint8_t sysid_;
  uint8_t compid_;
  uint8_t seq_ = 0;
};

}  // namespace nadir::mavlink
