// Per-sentence accounting through the live bridge over real ptys: a known,
// shuffled mix of good and bad INS sentences, line noise and altimeter lines
// goes in; the STATUS message must count every sentence exactly once
// (accepted + rejected by reason = sent), line noise as garbage bytes, and
// `malformed` = the rejected sentences and lines.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "processes/ins_bridge/bridge_runner.h"
#include "processes/ins_bridge/novatel_messages.h"
#include "processes/ins_bridge/pseudo_terminal.h"
#include "tests/common/test_support.h"
#include "tests/processes/ins_bridge/bridge_test_support.h"
#include "tests/processes/ins_bridge/test_sentences.h"

namespace nadir::ins_bridge {
namespace {

using testing::PvaFields;
using Bytes = std::vector<uint8_t>;

enum Reason { kAccepted, kCrc, kLength, kFields, kUnknownLog, kTruncated, kReasons };
const char* const kCounterOf[kReasons] = {"ins_sentences_accepted", "ins_rejected_crc",
                                          "ins_rejected_length",    "ins_rejected_fields",
                                          "ins_rejected_unknown_log", "ins_rejected_truncated"};

struct Item {
  Reason reason;
  Bytes bytes;
  int64_t garbage = 0;  // bytes of it counted as garbage (a rejected binary frame's rest is rescanned)
};

Bytes bytes_of(const std::string& text) { return {text.begin(), text.end()}; }

PvaFields pva_at(int i) {
  PvaFields p;
  p.seconds = 345600 + i * 0.01;
  return p;
}

// After a rejected binary frame the parser resumes at its second byte: the
// rest is line noise (CR and LF excepted, as between ASCII frames).
int64_t rescanned_garbage(const Bytes& frame) {
  return static_cast<int64_t>(std::count_if(frame.begin() + 1, frame.end(), [](uint8_t b) {
    return b != '\r' && b != '\n';
  }));
}

std::vector<Item> make_mix() {
  std::vector<Item> items;
  int n = 0;
  auto binary_pva = [&](const PvaFields& p, int length_override = -1) {
    return testing::binary_frame(kInspvaId, p.week, static_cast<uint32_t>(p.seconds * 1000), testing::inspvab_body(p),
                                 length_override);
  };
  for (int i = 0; i < 20; ++i) items.push_back({kAccepted, bytes_of(testing::inspvaa(pva_at(n++)))});
  for (int i = 0; i < 20; ++i) items.push_back({kAccepted, bytes_of(testing::inspvasa(pva_at(n++)))});
  for (int i = 0; i < 20; ++i) items.push_back({kAccepted, binary_pva(pva_at(n++))});
  for (int i = 0; i < 5; ++i) {
    items.push_back({kAccepted, bytes_of(testing::ascii_frame(
                                    '#', testing::long_header("INSSTDEVA", 2300, "345600.000"),
                                    {"0.5", "0.6", "0.9", "0.01", "0.02", "0.03", "0.1", "0.2", "0.4", "0", "0", "0",
                                     "0", "0"}))});
  }
  for (int i = 0; i < 7; ++i) {  // one character changed
    std::string text = testing::inspvaa(pva_at(n++));
    text[20 + i] = text[20 + i] == 'X' ? 'Y' : 'X';
    items.push_back({kCrc, bytes_of(text)});
  }
  for (int i = 0; i < 3; ++i) {
    Bytes frame = binary_pva(pva_at(n++));
    frame[40 + i] ^= 0x10;
    items.push_back({kCrc, frame, rescanned_garbage(frame)});
  }
  for (int i = 0; i < 4; ++i) {
    const Bytes frame = binary_pva(pva_at(n++), 80 + i);
    items.push_back({kLength, frame, rescanned_garbage(frame)});
  }
  for (int i = 0; i < 5; ++i) {  // 11 body fields, CRC good
    std::vector<std::string> body = pva_at(n++).fields();
    body.pop_back();
    items.push_back({kFields, bytes_of(testing::ascii_frame('#', testing::long_header("INSPVAA", 2300, "1.0"), body))});
  }
  for (int i = 0; i < 2; ++i) {  // latitude out of range, CRC good
    PvaFields p = pva_at(n++);
    p.lat = 200;
    items.push_back({kFields, binary_pva(p)});
  }
  for (int i = 0; i < 3; ++i) {
    items.push_back({kUnknownLog, bytes_of(testing::ascii_frame('#', testing::long_header("BESTPOSA", 2300, "1.0"),
                                                                {"SOL_COMPUTED", "SINGLE"}))});
  }
  for (int i = 0; i < 2; ++i) items.push_back({kUnknownLog, testing::binary_frame(42, 2300, 1, Bytes(72, 1))});
  for (int i = 0; i < 3; ++i) {  // cut by a line end
    const std::string text = testing::inspvaa(pva_at(n++));
    items.push_back({kTruncated, bytes_of(text.substr(0, 40 + 30 * i) + "\r\n")});
  }
  for (int i = 0; i < 2; ++i) {  // cut by the next sentence (the good one after it counts as accepted)
    const std::string text = testing::inspvaa(pva_at(n++));
    Bytes cut = bytes_of(text.substr(0, 60));
    const Bytes next = bytes_of(testing::inspvaa(pva_at(n++)));
    items.push_back({kTruncated, cut});
    items.push_back({kAccepted, next});
  }
  return items;
}

// Line noise: no sync byte, no line end.
Bytes noise(std::mt19937& rng, size_t size) {
  Bytes out;
  while (out.size() < size) {
    const auto b = static_cast<uint8_t>(rng());
    if (b != '#' && b != '%' && b != 0xAA && b != '\r' && b != '\n') out.push_back(b);
  }
  return out;
}

void write_all(PseudoTerminal& pty, const Bytes& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    done += pty.write(bytes.data() + done, bytes.size() - done);
    if (done < bytes.size()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

TEST(InsBridgeAccounting, EverySentenceIsCountedOnceAcceptedOrRejectedByReason) {
  const nadir::testing::TempDir folder("ins_bridge_accounting");
  PseudoTerminal ins(folder.file("ins"));
  PseudoTerminal alt(folder.file("alt"));
  BridgeOptions options = testing::test_options();
  options.ins.serial.device = ins.path();
  options.altimeter.serial.device = alt.path();
  options.ins.serial.stall_timeout_s = 30;  // the exchange is short; no stall may cut it
  options.altimeter.serial.stall_timeout_s = 30;
  testing::Collected got;
  std::unique_ptr<LcmBus> bus = testing::memq_bus(&got);
  BridgeRunner runner(options, *bus, "ins_bridge", 60.0);
  runner.step(0);  // opens both devices
  ASSERT_TRUE(runner.ins_open() && runner.altimeter_open());

  std::mt19937 rng(24);
  // Keep a truncated-by-next pair together: shuffle the others around it.
  std::vector<Item> items = make_mix();
  std::vector<std::vector<Item>> groups;
  for (size_t i = 0; i < items.size(); ++i) {
    const bool pair = items[i].reason == kTruncated && items[i].bytes.back() != '\n';
    groups.push_back({items[i]});
    if (pair) groups.back().push_back(items[++i]);
  }
  std::shuffle(groups.begin(), groups.end(), rng);
  int64_t sent[kReasons] = {};
  int64_t expected_garbage = 0;
  Bytes stream;
  for (size_t g = 0; g < groups.size(); ++g) {
    for (const Item& item : groups[g]) {
      ++sent[item.reason];
      expected_garbage += item.garbage;
      stream.insert(stream.end(), item.bytes.begin(), item.bytes.end());
    }
    if (g % 5 == 0) {  // line noise, then a line end so that it ends before the next sentence
      const Bytes junk = noise(rng, 100 + g * 10);
      stream.insert(stream.end(), junk.begin(), junk.end());
      expected_garbage += static_cast<int64_t>(junk.size());
      stream.push_back('\r');
      stream.push_back('\n');
    }
    if (g % 7 == 3) {  // stray syncs that begin no sentence: no log name, a short one, one not ending in 'A'
      for (const char* stray : {"# 12,", "#ab,", "#AA,", "%%", "#INSPVAX,", "#INS\r\n"}) {
        const std::string text = stray;
        stream.insert(stream.end(), text.begin(), text.end());
        expected_garbage += static_cast<int64_t>(std::count_if(text.begin(), text.end(), [](char c) {
          return c != '\r' && c != '\n';
        }));
      }
      stream.push_back('\r');
      stream.push_back('\n');
    }
  }
  const int64_t total_sent = sent[kAccepted] + sent[kCrc] + sent[kLength] + sent[kFields] + sent[kUnknownLog] +
                             sent[kTruncated];

  // Altimeter: good lines, unparsable lines and one overlong line.
  std::string alt_text;
  for (int i = 0; i < 30; ++i) alt_text += std::to_string(100 + i) + ".25 m 80%\r\n";
  for (int i = 0; i < 4; ++i) alt_text += "ERR" + std::to_string(i) + "\r\n";
  alt_text += std::string(300, '7') + "\r\n";

  // In chunks, as a serial line delivers them.
  for (size_t offset = 0; offset < stream.size(); offset += 512) {
    write_all(ins, Bytes(stream.begin() + static_cast<long>(offset),
                         stream.begin() + static_cast<long>(std::min(stream.size(), offset + 512))));
    runner.step(0);
  }
  write_all(alt, bytes_of(alt_text));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (std::chrono::steady_clock::now() < deadline &&
         (runner.bridge().ins_counts().bytes < static_cast<int64_t>(stream.size()) ||
          runner.bridge().altimeter_counts().lines < 34)) {
    runner.step(10);
  }
  runner.publish_status();
  testing::drain(*bus);
  ASSERT_FALSE(got.status.empty());
  const status_t& status = got.status.back();

  int64_t counted = 0;
  for (int r = 0; r < kReasons; ++r) {
    EXPECT_EQ(testing::counter(status, kCounterOf[r]), static_cast<double>(sent[r])) << kCounterOf[r];
    counted += static_cast<int64_t>(testing::counter(status, kCounterOf[r]));
  }
  EXPECT_EQ(counted, total_sent);
  EXPECT_EQ(testing::counter(status, "ins_sentences_rejected"), static_cast<double>(total_sent - sent[kAccepted]));
  EXPECT_EQ(testing::counter(status, "ins_garbage_bytes"), static_cast<double>(expected_garbage));
  EXPECT_EQ(testing::counter(status, "alt_lines_accepted"), 30.0);
  EXPECT_EQ(testing::counter(status, "alt_rejected_parse"), 4.0);
  EXPECT_EQ(testing::counter(status, "alt_rejected_overlong"), 1.0);
  EXPECT_EQ(testing::counter(status, "alt_lines_rejected"), 5.0);
  EXPECT_EQ(status.malformed, total_sent - sent[kAccepted] + 5);
  EXPECT_EQ(status.errors, 0);
  EXPECT_EQ(status.received, total_sent + 35);
  // Accepted: 5 INSSTDEV (attached, not published) and the INSPVA frames, all published.
  EXPECT_EQ(static_cast<int64_t>(got.ins.size()), sent[kAccepted] - 5);
  std::printf("[ FIGURE ] accounting over a pty: %lld sentences sent = %lld accepted + %lld CRC + %lld length + "
              "%lld fields + %lld unknown log + %lld truncated; %lld garbage bytes; malformed %lld\n",
              static_cast<long long>(total_sent), static_cast<long long>(sent[kAccepted]),
              static_cast<long long>(sent[kCrc]), static_cast<long long>(sent[kLength]),
              static_cast<long long>(sent[kFields]), static_cast<long long>(sent[kUnknownLog]),
              static_cast<long long>(sent[kTruncated]), static_cast<long long>(expected_garbage),
              static_cast<long long>(status.malformed));
}

}  // namespace
}  // namespace nadir::ins_bridge
