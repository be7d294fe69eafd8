#include <gtest/gtest.h>

#include "common/log_file.h"
#include "tests/common/test_support.h"

namespace nadir {
namespace {

// Writes n records with payloads of distinct sizes and returns their offsets.
std::vector<uint64_t> write_sample_log(const std::string& path, int n) {
  LogWriter writer(path);
  std::vector<uint64_t> offsets;
  uint64_t offset = 0;
  for (int i = 0; i < n; ++i) {
    std::vector<uint8_t> payload(100 + i, static_cast<uint8_t>(i));
    const std::string channel = i % 2 == 0 ? "INS" : "CAMERA_IMAGE";
    writer.write(1000 + i, channel, payload.data(), payload.size());
    offsets.push_back(offset);
    offset += 28 + channel.size() + payload.size();
  }
  writer.flush();
  return offsets;
}

TEST(LogFile, RoundTrip) {
  testing::TempDir dir("log");
  write_sample_log(dir.file("a.lcmlog"), 10);
  LogReader reader(dir.file("a.lcmlog"));
  LogEvent event;
  int count = 0;
  while (reader.next(&event)) {
    EXPECT_EQ(event.event_number, count);
    EXPECT_EQ(event.timestamp, 1000 + count);
    EXPECT_EQ(event.size, static_cast<size_t>(100 + count));
    EXPECT_EQ(event.data[0], static_cast<uint8_t>(count));
    ++count;
  }
  EXPECT_EQ(count, 10);
  EXPECT_EQ(reader.corrupt_records(), 0);
  EXPECT_FALSE(reader.truncated());
}

TEST(LogFile, TruncatedLogIsReadUpToTheDamage) {
  testing::TempDir dir("log");
  const auto offsets = write_sample_log(dir.file("a.lcmlog"), 10);
  auto bytes = testing::read_file_bytes(dir.file("a.lcmlog"));
  bytes.resize(offsets[9] + 40);  // cut inside the last record
  testing::write_file_bytes(dir.file("cut.lcmlog"), bytes);
  LogReader reader(dir.file("cut.lcmlog"));
  LogEvent event;
  int count = 0;
  while (reader.next(&event)) ++count;
  EXPECT_EQ(count, 9);
  EXPECT_TRUE(reader.truncated());
  ASSERT_EQ(reader.damage().size(), 1u);
  EXPECT_EQ(reader.damage()[0].offset, offsets[9]);
  EXPECT_NE(reader.damage_report().find("byte " + std::to_string(offsets[9])), std::string::npos);
}

TEST(LogFile, CorruptRecordsAreSkippedCountedAndLocated) {
  testing::TempDir dir("log");
  const auto offsets = write_sample_log(dir.file("a.lcmlog"), 10);
  auto bytes = testing::read_file_bytes(dir.file("a.lcmlog"));
  bytes[offsets[3]] ^= 0xFF;            // broken sync word
  bytes[offsets[6] + 24] = 0x7F;        // absurd data length
  bytes[offsets[8] + 27] ^= 0x01;       // data length off by one
  testing::write_file_bytes(dir.file("bad.lcmlog"), bytes);
  LogReader reader(dir.file("bad.lcmlog"));
  LogEvent event;
  std::vector<int64_t> seen;
  while (reader.next(&event)) seen.push_back(event.event_number);
  EXPECT_EQ(seen, (std::vector<int64_t>{0, 1, 2, 4, 5, 7, 9}));
  ASSERT_EQ(reader.corrupt_records(), 3);
  EXPECT_EQ(reader.damage()[0].offset, offsets[3]);
  EXPECT_EQ(reader.damage()[1].offset, offsets[6]);
  EXPECT_EQ(reader.damage()[2].offset, offsets[8]);
  EXPECT_FALSE(reader.truncated());
}

TEST(LogFile, GarbageBetweenRecordsIsSkipped) {
  testing::TempDir dir("log");
  const auto offsets = write_sample_log(dir.file("a.lcmlog"), 4);
  auto bytes = testing::read_file_bytes(dir.file("a.lcmlog"));
  bytes.insert(bytes.begin() + static_cast<long>(offsets[2]), 37, 0xAB);
  testing::write_file_bytes(dir.file("junk.lcmlog"), bytes);
  LogReader reader(dir.file("junk.lcmlog"));
  LogEvent event;
  int count = 0;
  while (reader.next(&event)) ++count;
  EXPECT_EQ(count, 4);
  ASSERT_EQ(reader.corrupt_records(), 1);
  EXPECT_EQ(reader.damage()[0].offset, offsets[2]);
  EXPECT_EQ(reader.damage()[0].skipped_bytes, 37u);
}

TEST(LogFile, MissingFileNamesThePath) {
  try {
    LogReader reader("/nonexistent/x.lcmlog");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/x.lcmlog"), std::string::npos);
  }
}

}  // namespace
}  // namespace nadir
