// Fuzzed frame parser: streams of good frames of every message the codec
// knows (v1 and v2, random field bytes) with random byte runs, truncated
// frames and bit-flipped frames between them, fed in random read sizes (a
// serial line) or one item per datagram (UDP). Exact accounting: every good
// frame is passed, byte for byte, in order, and nothing else; every bad item
// is one rejected span. Run under ASan/UBSan in the sanitized test stage.
// NADIR_FUZZ_ITERATIONS / NADIR_FUZZ_SEED for longer runs.

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <set>

#include "processes/mavlink_bridge/mavlink_frame.h"

namespace nadir::mavlink {
namespace {

int iterations() {
  const char* text = std::getenv("NADIR_FUZZ_ITERATIONS");
  return text ? std::atoi(text) : 20000;
}
uint32_t seed() {
  const char* text = std::getenv("NADIR_FUZZ_SEED");
  return text ? static_cast<uint32_t>(std::strtoul(text, nullptr, 10)) : 19u;
}

struct Item {
  std::vector<uint8_t> bytes;
  bool good = false;
};

struct Expected {
  uint32_t msgid;
  uint8_t seq;
  std::vector<uint8_t> payload;
};

class Generator {
 public:
  explicit Generator(uint32_t s) : rng_(s), encoder_(3, 4) {
    for_each_message_type([&](auto m) { infos_.push_back(message_info<decltype(m)>()); });
  }

  Item good_frame(std::vector<Expected>* expected) {
    const MessageInfo& info = infos_[pick(infos_.size())];
    const int version = (info.id < 256 && coin()) ? 1 : 2;
    std::vector<uint8_t> payload(info.length);
    for (uint8_t& b : payload) b = static_cast<uint8_t>(rng_());
    const uint8_t seq = encoder_.next_seq();
    Item item{encoder_.encode_raw(info.id, info.crc_extra, payload, info.base_length, version), true};
    const size_t header = version == 2 ? 10 : 6;
    expected->push_back({info.id, seq,
                         std::vector<uint8_t>(item.bytes.begin() + static_cast<std::ptrdiff_t>(header),
                                              item.bytes.end() - 2)});
    return item;
  }

  // A bad item that holds a frame passing the CRC on its own is not bad:
  // MAVLink's 16-bit CRC lets 1 in 65,536 corruptions through. Drawn again.
  Item bad_item() {
    for (;;) {
      Item item = draw_bad_item();
      FrameParserOptions strict;
      strict.skip_unknown = false;
      FrameParser alone(strict);
      std::vector<Frame> frames;
      alone.feed(item.bytes.data(), item.bytes.size(), 0, 0.0, &frames);
      alone.end_of_datagram(&frames);
      if (frames.empty()) return item;
      ++collisions_;
    }
  }
  int64_t collisions() const { return collisions_; }

 private:
  Item draw_bad_item() {
    std::vector<Expected> ignored;
    Item item = good_frame(&ignored);
    item.good = false;
    switch (pick(3)) {
      case 0: {  // random bytes, start bytes included
        item.bytes.resize(1 + pick(300));
        for (uint8_t& b : item.bytes) b = coin(8) ? (coin() ? kStxV2 : kStxV1) : static_cast<uint8_t>(rng_());
        break;
      }
      case 1:  // cut inside its header or payload; a frame cut inside its CRC gets
               // the next frame's start byte as CRC byte and passes 1 time in 256:
               // an ambiguity of the framing itself, which no parser can resolve
        item.bytes.resize(1 + pick(item.bytes.size() - 3));
        break;
      default: {  // 1..3 distinct bits flipped (the same bit twice would undo itself)
        const size_t flips = 1 + pick(3);
        std::set<size_t> bits;
        while (bits.size() < flips) bits.insert(pick(item.bytes.size() * 8));
        for (size_t bit : bits) item.bytes[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
        break;
      }
    }
    return item;
  }


 public:
  size_t pick(size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }
  bool coin(int one_in = 2) { return pick(static_cast<size_t>(one_in)) == 0; }

 private:
  int64_t collisions_ = 0;
  std::mt19937 rng_;
  FrameEncoder encoder_;
  std::vector<MessageInfo> infos_;
};

void expect_same(const std::vector<Frame>& got, const std::vector<Expected>& expected) {
  for (size_t i = 0; i < std::min(got.size(), expected.size()); ++i) {
    ASSERT_EQ(got[i].msgid, expected[i].msgid) << "frame " << i << " seq " << int{got[i].seq} << " v" << got[i].version
                                               << " len " << int{got[i].payload_length} << ", expected seq "
                                               << int{expected[i].seq} << " previous " << got[i - 1].msgid << "/"
                                               << int{got[i - 1].seq} << " next expected " << expected[i + 1].msgid;
    ASSERT_EQ(got[i].seq, expected[i].seq) << "frame " << i;
    ASSERT_EQ(std::vector<uint8_t>(got[i].payload.begin(), got[i].payload.begin() + got[i].payload_length),
              expected[i].payload)
        << "frame " << i;
  }
  ASSERT_EQ(got.size(), expected.size());
}

struct Outcome {
  int64_t good = 0;
  int64_t bad = 0;
  int64_t redrawn = 0;  // bad items that passed the CRC on their own
};

// Serial: bad items always between good frames, read in random sizes.
Outcome fuzz_stream(const FrameParserOptions& options, std::vector<Frame>* got, std::vector<Expected>* expected,
                    FrameCounts* counts) {
  Generator gen(seed());
  std::vector<uint8_t> stream;
  Outcome outcome;
  for (int i = 0; i < iterations(); ++i) {
    const Item item = (i % 2 == 1 && gen.coin()) ? gen.bad_item() : gen.good_frame(expected);
    (item.good ? outcome.good : outcome.bad) += 1;
    stream.insert(stream.end(), item.bytes.begin(), item.bytes.end());
  }
  FrameParser parser(options);
  for (size_t pos = 0; pos < stream.size();) {
    const size_t n = std::min(stream.size() - pos, 1 + gen.pick(64));
    parser.feed(stream.data() + pos, n, 0, 0.0, got);
    pos += n;
  }
  parser.end_of_datagram(got);
  *counts = parser.counts();
  EXPECT_EQ(counts->bytes, static_cast<int64_t>(stream.size()));
  outcome.redrawn = gen.collisions();
  return outcome;
}

// UDP: one item per datagram, bad ones may follow each other.
Outcome fuzz_datagrams(const FrameParserOptions& options, std::vector<Frame>* got, std::vector<Expected>* expected,
                       FrameCounts* counts) {
  Generator gen(seed() + 1);
  FrameParser parser(options);
  Outcome outcome;
  for (int i = 0; i < iterations(); ++i) {
    const Item item = gen.coin(3) ? gen.bad_item() : gen.good_frame(expected);
    (item.good ? outcome.good : outcome.bad) += 1;
    parser.feed(item.bytes.data(), item.bytes.size(), 0, 0.0, got);
    parser.end_of_datagram(got);
  }
  *counts = parser.counts();
  outcome.redrawn = gen.collisions();
  return outcome;
}

TEST(MavlinkFrameFuzz, StrictStreamPassesEveryGoodFrameAndCountsEveryBadItemOnce) {
  FrameParserOptions strict;
  strict.skip_unknown = false;
  std::vector<Frame> got;
  std::vector<Expected> expected;
  FrameCounts counts;
  const Outcome o = fuzz_stream(strict, &got, &expected, &counts);
  expect_same(got, expected);
  EXPECT_EQ(counts.accepted(), o.good);
  EXPECT_EQ(counts.rejected_spans, o.bad);
  std::printf("stream: %lld good frames passed, %lld bad items -> %lld rejected spans (%lld garbage bytes; crc %lld, "
              "length %lld, flags %lld, unknown id %lld, truncated %lld); %lld bad items drawn again (valid by CRC)\n",
              static_cast<long long>(o.good), static_cast<long long>(o.bad),
              static_cast<long long>(counts.rejected_spans), static_cast<long long>(counts.garbage_bytes),
              static_cast<long long>(counts.bad_crc), static_cast<long long>(counts.bad_length),
              static_cast<long long>(counts.bad_flags), static_cast<long long>(counts.unknown_id),
              static_cast<long long>(counts.truncated), static_cast<long long>(o.redrawn));
}

TEST(MavlinkFrameFuzz, StrictDatagramsPassEveryGoodFrameAndRejectEveryBadDatagram) {
  FrameParserOptions strict;
  strict.skip_unknown = false;
  std::vector<Frame> got;
  std::vector<Expected> expected;
  FrameCounts counts;
  const Outcome o = fuzz_datagrams(strict, &got, &expected, &counts);
  expect_same(got, expected);
  EXPECT_EQ(counts.accepted(), o.good);
  EXPECT_EQ(counts.rejected_spans, o.bad);
  std::printf("datagrams: %lld good frames passed, %lld bad datagrams -> %lld rejected spans; %lld drawn again\n",
              static_cast<long long>(o.good), static_cast<long long>(o.bad),
              static_cast<long long>(counts.rejected_spans), static_cast<long long>(o.redrawn));
}

// As configured live (unknown ids skipped whole when what follows confirms
// where they end): the good frames are still exactly the ones passed; a bad
// item can only be taken for an unknown frame, never for a good one.
void expect_live(bool datagrams) {
  std::vector<Frame> got;
  std::vector<Expected> expected;
  FrameCounts counts;
  const Outcome o =
      datagrams ? fuzz_datagrams({}, &got, &expected, &counts) : fuzz_stream({}, &got, &expected, &counts);
  expect_same(got, expected);
  EXPECT_EQ(counts.accepted(), o.good);
  EXPECT_LE(counts.rejected_spans, o.bad);
  EXPECT_GE(counts.rejected_spans + counts.unknown_skipped, o.bad);
  std::printf("%s, live options: %lld good frames passed, %lld bad items -> %lld rejected spans, %lld taken for "
              "unknown frames\n",
              datagrams ? "datagrams" : "stream", static_cast<long long>(o.good), static_cast<long long>(o.bad),
              static_cast<long long>(counts.rejected_spans), static_cast<long long>(counts.unknown_skipped));
}

TEST(MavlinkFrameFuzz, LiveOptionsStreamPassesExactlyTheGoodFrames) { expect_live(false); }
TEST(MavlinkFrameFuzz, LiveOptionsDatagramsPassExactlyTheGoodFrames) { expect_live(true); }

}  // namespace
}  // namespace nadir::mavlink
