// Random mutation of valid INS and altimeter streams (truncation, insertion,
// deletion, duplication, bit flips) fed in random chunk sizes through the
// parsers and the whole bridge on a memq:// bus. Seeded and bounded so it runs
// in seconds in CI (under ASan/UBSan in the sanitizer build); longer runs:
//   NADIR_FUZZ_ITERATIONS=200000 NADIR_FUZZ_SEED=7 nadir_test_ins_bridge_fuzz

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <random>

#include "processes/ins_bridge/altimeter_parser.h"
#include "processes/ins_bridge/ins_bridge.h"
#include "processes/ins_bridge/line_splitter.h"
#include "processes/ins_bridge/novatel_parser.h"
#include "tests/processes/ins_bridge/bridge_test_support.h"
#include "tests/processes/ins_bridge/test_sentences.h"

namespace nadir::ins_bridge {
namespace {

using testing::PvaFields;

long env_or(const char* name, long fallback) {
  const char* value = std::getenv(name);
  return value ? std::strtol(value, nullptr, 10) : fallback;
}

// A valid stream of every INS format and its frame count.
std::vector<uint8_t> valid_ins_stream(int* frames) {
  std::vector<uint8_t> s;
  *frames = 0;
  for (int i = 0; i < 12; ++i) {
    PvaFields p;
    p.seconds = 345600 + i * 0.01;
    p.roll = -180 + 30 * i;
    p.azimuth = 30 * i;
    switch (i % 5) {
      case 0: testing::append(&s, testing::inspvaa(p)); break;
      case 1: testing::append(&s, testing::inspvasa(p)); break;
      case 2:
        testing::append(&s, testing::binary_frame(kInspvaId, p.week, static_cast<uint32_t>(p.seconds * 1000),
                                                  testing::inspvab_body(p)));
        break;
      case 3:
        testing::append(&s, testing::ascii_frame('#', testing::long_header("INSSTDEVA", p.week, "345600.0"),
                                                 {"0.1", "0.1", "0.2", "0.01", "0.01", "0.02", "0.05", "0.05", "0.1",
                                                  "3", "0", "0", "0", "0"}));
        break;
      default:
        testing::append(&s, testing::binary_frame(kInsstdevId, p.week, 345600000,
                                                  testing::insstdevb_body({1, 1, 2, 0.1f, 0.1f, 0.2f, 0.5f, 0.5f, 1},
                                                                          3, 0)));
    }
    ++*frames;
  }
  return s;
}

std::vector<uint8_t> valid_altimeter_stream() {
  std::vector<uint8_t> s;
  testing::append(&s, "123.45\r\n87.20 m 64%\r\n--.--\r\n-1.00\r\n1500.5 m,100\r\n0.10\r\n");
  return s;
}

enum class Mutation { kFlip, kTruncate, kInsert, kDelete, kDuplicate };

// Applies 1..4 random mutations; returns the number of bit flips when only flips were used, else -1.
int mutate(std::vector<uint8_t>* s, std::mt19937_64& rng) {
  const int count = 1 + static_cast<int>(rng() % 4);
  bool flips_only = rng() % 2 == 0;
  for (int m = 0; m < count && !s->empty(); ++m) {
    const Mutation kind = flips_only ? Mutation::kFlip : static_cast<Mutation>(rng() % 5);
    const size_t at = rng() % s->size();
    switch (kind) {
      case Mutation::kFlip: (*s)[at] ^= static_cast<uint8_t>(1u << (rng() % 8)); break;
      case Mutation::kTruncate: s->resize(at); break;
      case Mutation::kInsert: {
        std::vector<uint8_t> junk(rng() % 64);
        for (auto& b : junk) {
          // Bias toward bytes that matter to the framers.
          static const uint8_t kInteresting[] = {'#', '%', '*', ';', ',', '\r', '\n', 0xAA, 0x44, 0x12, 0x13, 0};
          b = rng() % 3 == 0 ? kInteresting[rng() % sizeof kInteresting] : static_cast<uint8_t>(rng());
        }
        s->insert(s->begin() + static_cast<long>(at), junk.begin(), junk.end());
        break;
      }
      case Mutation::kDelete: {
        const size_t n = std::min(s->size() - at, static_cast<size_t>(rng() % 40));
        s->erase(s->begin() + static_cast<long>(at), s->begin() + static_cast<long>(at + n));
        break;
      }
      case Mutation::kDuplicate: {
        const size_t n = std::min(s->size() - at, static_cast<size_t>(rng() % 120));
        std::vector<uint8_t> copy(s->begin() + static_cast<long>(at), s->begin() + static_cast<long>(at + n));
        s->insert(s->begin() + static_cast<long>(rng() % s->size()), copy.begin(), copy.end());
        break;
      }
    }
  }
  return flips_only ? count : -1;
}

TEST(InsBridgeFuzz, MutatedStreamsNeverBreakTheParsersOrTheBridge) {
  const long iterations = env_or("NADIR_FUZZ_ITERATIONS", 10000);
  const uint64_t seed = static_cast<uint64_t>(env_or("NADIR_FUZZ_SEED", 20261123));
  std::mt19937_64 rng(seed);
  int frames_in_valid = 0;
  const std::vector<uint8_t> ins_valid = valid_ins_stream(&frames_in_valid);
  const std::vector<uint8_t> alt_valid = valid_altimeter_stream();

  // One bridge for the whole run: it must stay healthy across all the damage.
  testing::Collected got;
  std::unique_ptr<LcmBus> bus = testing::memq_bus(&got);
  InsBridge bridge(testing::test_options(), *bus);
  NumberUnitOptions nu;
  nu.prefix = "D=";
  nu.quality_prefix = "Q=";
  nu.no_return_token = "NONE";
  const NumberUnitParser number_unit(nu);
  const LightwareAsciiParser lightware;

  int64_t total_frames = 0, flip_runs = 0;
  int64_t clock = 1700000000000000;
  for (long it = 0; it < iterations; ++it) {
    std::vector<uint8_t> ins = ins_valid;
    std::vector<uint8_t> alt = alt_valid;
    const int flips = mutate(&ins, rng);
    mutate(&alt, rng);

    // Standalone parser: every decoded frame is within limits, and bit flips
    // cost at most one frame each (the framer resynchronises).
    NovatelParser parser;
    std::vector<NovatelFrame> frames;
    size_t pos = 0;
    while (pos < ins.size()) {
      const size_t n = std::min(ins.size() - pos, 1 + static_cast<size_t>(rng() % 300));
      parser.feed(ins.data() + pos, n, clock, 40.0, &frames);
      pos += n;
    }
    for (const NovatelFrame& f : frames) {
      const std::string why =
          f.kind == NovatelFrame::Kind::kInsPva ? check_limits(f.pva) : check_limits(f.stddev);
      ASSERT_TRUE(why.empty()) << why;
      ASSERT_LE(f.offset + f.size, ins.size());
    }
    ASSERT_EQ(parser.counts().bytes, static_cast<int64_t>(ins.size()));
    if (flips > 0) {
      ++flip_runs;
      ASSERT_GE(static_cast<int>(frames.size()), frames_in_valid - flips) << "iteration " << it;
    }
    total_frames += static_cast<int64_t>(frames.size());

    LineSplitter splitter;
    std::vector<SerialLine> lines;
    splitter.feed(alt.data(), alt.size(), clock, 87.0, &lines);
    for (const SerialLine& line : lines) {
      ASSERT_LE(line.text.size(), LineSplitter::kMaxLine);
      const AltimeterReading a = lightware.parse(line.text);
      const AltimeterReading b = number_unit.parse(line.text);
      ASSERT_TRUE(!a.parsed || a.no_return || std::isfinite(a.range_m));
      ASSERT_TRUE(!b.parsed || b.no_return || std::isfinite(b.range_m));
      ASSERT_TRUE(a.parsed || !a.error.empty());
    }

    // The whole bridge, fed the same damage in one go.
    bridge.on_ins_bytes(ins.data(), ins.size(), clock);
    bridge.on_altimeter_bytes(alt.data(), alt.size(), clock);
    testing::drain(*bus);
    clock += 100000;
  }
  const NovatelParserCounts& c = bridge.ins_counts();
  std::printf("[ FIGURE ] fuzz seed %llu, %ld iterations (%lld bit-flip runs): %lld frames decoded, %lld CRC "
              "failures, %lld bad lengths, %lld truncated, %lld field errors, %lld garbage bytes; bridge published "
              "%lld INS, %lld ALTIMETER\n",
              static_cast<unsigned long long>(seed), iterations, static_cast<long long>(flip_runs),
              static_cast<long long>(total_frames), static_cast<long long>(c.crc_failures),
              static_cast<long long>(c.bad_length), static_cast<long long>(c.truncated),
              static_cast<long long>(c.field_errors), static_cast<long long>(c.garbage_bytes),
              static_cast<long long>(bridge.ins_published()), static_cast<long long>(bridge.altimeter_published()));
  EXPECT_GT(c.crc_failures, 0);
  EXPECT_GT(bridge.ins_published(), 0);
  EXPECT_EQ(static_cast<int64_t>(got.ins.size()), bridge.ins_published());
  for (const ins_t& m : got.ins) {
    ASSERT_TRUE(std::isfinite(m.roll) && std::isfinite(m.pitch) && std::isfinite(m.yaw));
    ASSERT_LE(std::fabs(m.yaw), M_PI);
  }
  // After all that the bridge still decodes a clean frame.
  const int64_t before = bridge.ins_published();
  const std::string clean = "\r\n" + testing::inspvaa(PvaFields{});
  PvaFields later;
  later.seconds = 400000;
  const std::string clean2 = testing::inspvaa(later);
  bridge.on_ins_bytes(reinterpret_cast<const uint8_t*>(clean.data()), clean.size(), clock);
  bridge.on_ins_bytes(reinterpret_cast<const uint8_t*>(clean2.data()), clean2.size(), clock + 1000);
  EXPECT_GE(bridge.ins_published(), before + 1);
}

}  // namespace
}  // namespace nadir::ins_bridge
