// McapWriter: the file's framing (magic, header, data end, footer, summary
// offsets) and CRCs, checked byte by byte against the specification. The
// complete check against an independent reader is mcap_export_test.sh.
#include "tools/export/mcap_writer.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

namespace nadir {
namespace {

uint64_t u64(const std::string& b, size_t at) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(b[at + i]);
  return v;
}
uint32_t u32(const std::string& b, size_t at) { return static_cast<uint32_t>(u64(b.substr(at, 4) + std::string(4, '\0'), 0)); }

TEST(Crc32, MatchesTheStandardCheckValue) {
  const char* text = "123456789";
  EXPECT_EQ(crc32_update(0, reinterpret_cast<const uint8_t*>(text), 9), 0xCBF43926u);
  // Incremental equals one pass.
  const uint32_t part = crc32_update(0, reinterpret_cast<const uint8_t*>(text), 4);
  EXPECT_EQ(crc32_update(part, reinterpret_cast<const uint8_t*>(text + 4), 5), 0xCBF43926u);
}

TEST(McapWriter, FramingOffsetsAndCrcsFollowTheSpecification) {
  const std::string path = testing::TempDir() + "/writer_test.mcap";
  {
    McapWriterOptions o;
    o.chunk_size = 200;  // several chunks
    McapWriter w(path, o);
    const uint16_t schema = w.add_schema("s", "jsonschema", "{\"type\":\"object\"}");
    const uint16_t a = w.add_channel(schema, "A", "json", {{"k", "v"}});
    const uint16_t b = w.add_channel(schema, "B", "json", {});
    for (uint32_t i = 0; i < 20; ++i) {
      const std::string data = "{\"i\":" + std::to_string(i) + "}";
      w.write_message(i % 2 ? b : a, i / 2, 1000 + i, 2000 + i, reinterpret_cast<const uint8_t*>(data.data()),
                      data.size());
    }
    EXPECT_THROW(w.write_message(9, 0, 0, 0, nullptr, 0), std::invalid_argument);
    w.close();
    EXPECT_GT(w.chunk_count(), 2u);
    EXPECT_EQ(w.message_count(), 20u);
  }
  std::ifstream f(path, std::ios::binary);
  const std::string b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const std::string magic("\x89MCAP0\r\n", 8);
  ASSERT_GT(b.size(), 64u);
  EXPECT_EQ(b.substr(0, 8), magic);
  EXPECT_EQ(b.substr(b.size() - 8), magic);
  EXPECT_EQ(static_cast<uint8_t>(b[8]), 0x01);  // Header
  // Footer: opcode 0x02, length 20, summary start, summary offset start, CRC.
  const size_t footer = b.size() - 8 - 29;
  ASSERT_EQ(static_cast<uint8_t>(b[footer]), 0x02);
  EXPECT_EQ(u64(b, footer + 1), 20u);
  const uint64_t summary_start = u64(b, footer + 9), summary_offsets = u64(b, footer + 17);
  EXPECT_EQ(crc32_update(0, reinterpret_cast<const uint8_t*>(b.data()) + summary_start, footer + 25 - summary_start),
            u32(b, footer + 25));
  // Data End just before the summary, with the CRC of everything before it.
  const size_t data_end = summary_start - 13;
  ASSERT_EQ(static_cast<uint8_t>(b[data_end]), 0x0F);
  EXPECT_EQ(crc32_update(0, reinterpret_cast<const uint8_t*>(b.data()), data_end), u32(b, data_end + 9));
  // The summary starts with the Schema record; summary offsets point at records of their group's opcode.
  EXPECT_EQ(static_cast<uint8_t>(b[summary_start]), 0x03);
  int groups = 0;
  for (size_t at = summary_offsets; at < footer; at += 1 + 8 + 17, ++groups) {
    ASSERT_EQ(static_cast<uint8_t>(b[at]), 0x0E);
    const uint8_t op = static_cast<uint8_t>(b[at + 9]);
    EXPECT_EQ(static_cast<uint8_t>(b[u64(b, at + 10)]), op);
  }
  EXPECT_EQ(groups, 4);  // Schema, Channel, Statistics, Chunk Index
}

}  // namespace
}  // namespace nadir
