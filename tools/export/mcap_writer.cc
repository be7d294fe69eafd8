#include "tools/export/mcap_writer.h"

#include <array>
#include <stdexcept>

namespace nadir {
namespace {

constexpr char kMagic[] = "\x89MCAP0\r\n";
enum Op : uint8_t {
  kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kChunk = 0x06,
  kMessageIndex = 0x07, kChunkIndex = 0x08, kStatistics = 0x0B, kSummaryOffset = 0x0E, kDataEnd = 0x0F,
};

// Little-endian primitives of the MCAP encoding.
void put_u8(std::string* b, uint8_t v) { b->push_back(static_cast<char>(v)); }
template <class T>
void put_le(std::string* b, T v) {
  for (size_t i = 0; i < sizeof(T); ++i) b->push_back(static_cast<char>((static_cast<uint64_t>(v) >> (8 * i)) & 0xff));
}
void put_u16(std::string* b, uint16_t v) { put_le(b, v); }
void put_u32(std::string* b, uint32_t v) { put_le(b, v); }
void put_u64(std::string* b, uint64_t v) { put_le(b, v); }
void put_string(std::string* b, const std::string& s) {
  put_u32(b, static_cast<uint32_t>(s.size()));
  b->append(s);
}
std::string record(uint8_t op, const std::string& content) {
  std::string r;
  put_u8(&r, op);
  put_u64(&r, content.size());
  return r + content;
}

}  // namespace

uint32_t crc32_update(uint32_t crc, const uint8_t* data, size_t size) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xff] ^ (crc >> 8);
  return ~crc;
}

McapWriter::McapWriter(const std::string& path, const McapWriterOptions& options) : path_(path), options_(options) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw std::runtime_error(path + ": cannot create");
  write(std::string(kMagic, 8));
  std::string header;
  put_string(&header, options_.profile);
  put_string(&header, options_.library);
  write(record(kHeader, header));
}

McapWriter::~McapWriter() {
  if (!closed_) {
    try {
      close();
    } catch (...) {
    }
  }
}

void McapWriter::write(const std::string& bytes) {
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
    throw std::runtime_error(path_ + ": write failed at byte " + std::to_string(position_));
  if (in_data_section_) data_crc_ = crc32_update(data_crc_, reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  position_ += bytes.size();
}

uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
  const uint16_t id = static_cast<uint16_t>(schema_records_.size() + 1);
  std::string c;
  put_u16(&c, id);
  put_string(&c, name);
  put_string(&c, encoding);
  put_string(&c, data);  // bytes with a uint32 length, like a string
  schema_records_.push_back(record(kSchema, c));
  chunk_ += schema_records_.back();  // before any message that needs it
  return id;
}

uint16_t McapWriter::add_channel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                                 const std::map<std::string, std::string>& metadata) {
  const uint16_t id = static_cast<uint16_t>(channel_records_.size() + 1);
  std::string c, map;
  put_u16(&c, id);
  put_u16(&c, schema_id);
  put_string(&c, topic);
  put_string(&c, message_encoding);
  for (const auto& [k, v] : metadata) {
    put_string(&map, k);
    put_string(&map, v);
  }
  put_u32(&c, static_cast<uint32_t>(map.size()));
  c += map;
  channel_records_.push_back(record(kChannel, c));
  chunk_ += channel_records_.back();
  channel_counts_[id];  // every channel in the statistics, even without messages
  return id;
}

void McapWriter::write_message(uint16_t channel_id, uint32_t sequence, uint64_t log_time, uint64_t publish_time,
                               const uint8_t* data, size_t size) {
  if (channel_id == 0 || channel_id > channel_records_.size())
    throw std::invalid_argument(path_ + ": message on channel id " + std::to_string(channel_id) + " never added");
  chunk_index_[channel_id].emplace_back(log_time, chunk_.size());
  put_u8(&chunk_, kMessage);
  put_u64(&chunk_, 2 + 4 + 8 + 8 + size);
  put_u16(&chunk_, channel_id);
  put_u32(&chunk_, sequence);
  put_u64(&chunk_, log_time);
  put_u64(&chunk_, publish_time);
  chunk_.append(reinterpret_cast<const char*>(data), size);
  chunk_start_ = std::min(chunk_start_, log_time);
  chunk_end_ = std::max(chunk_end_, log_time);
  start_time_ = std::min(start_time_, log_time);
  end_time_ = std::max(end_time_, log_time);
  ++channel_counts_[channel_id];
  ++message_count_;
  if (chunk_.size() >= options_.chunk_size) flush_chunk();
}

void McapWriter::flush_chunk() {
  if (chunk_.empty()) return;
  const bool has_messages = !chunk_index_.empty();
  std::string c;
  put_u64(&c, has_messages ? chunk_start_ : 0);
  put_u64(&c, has_messages ? chunk_end_ : 0);
  put_u64(&c, chunk_.size());
  put_u32(&c, crc32_update(0, reinterpret_cast<const uint8_t*>(chunk_.data()), chunk_.size()));
  put_string(&c, "");  // no compression
  put_u64(&c, chunk_.size());
  c += chunk_;
  ChunkIndex index{has_messages ? chunk_start_ : 0, has_messages ? chunk_end_ : 0, position_, 0, 0, chunk_.size(), {}};
  const std::string chunk_record = record(kChunk, c);
  write(chunk_record);
  index.length = chunk_record.size();
  const uint64_t indexes_start = position_;
  for (const auto& [channel, entries] : chunk_index_) {
    std::string m;
    put_u16(&m, channel);
    put_u32(&m, static_cast<uint32_t>(entries.size() * 16));
    for (const auto& [time, offset] : entries) {
      put_u64(&m, time);
      put_u64(&m, offset);
    }
    index.message_index_offsets[channel] = position_;
    const std::string r = record(kMessageIndex, m);
    write(r);
  }
  index.message_index_length = position_ - indexes_start;
  chunk_indexes_.push_back(index);
  chunk_.clear();
  chunk_index_.clear();
  chunk_start_ = UINT64_MAX;
  chunk_end_ = 0;
}

void McapWriter::close() {
  if (closed_) return;
  closed_ = true;
  flush_chunk();
  std::string data_end;
  put_u32(&data_end, data_crc_);  // everything from the magic on
  in_data_section_ = false;
  write(record(kDataEnd, data_end));

  std::string summary;
  const uint64_t summary_start = position_;
  struct Group { uint8_t op; uint64_t start, length; };
  std::vector<Group> groups;
  auto add_group = [&](uint8_t op, const std::vector<std::string>& records) {
    if (records.empty()) return;
    const uint64_t start = summary_start + summary.size();
    for (const std::string& r : records) summary += r;
    groups.push_back({op, start, summary_start + summary.size() - start});
  };
  add_group(kSchema, schema_records_);
  add_group(kChannel, channel_records_);
  std::string stats;
  put_u64(&stats, message_count_);
  put_u16(&stats, static_cast<uint16_t>(schema_records_.size()));
  put_u32(&stats, static_cast<uint32_t>(channel_records_.size()));
  put_u32(&stats, 0);  // attachments
  put_u32(&stats, 0);  // metadata
  put_u32(&stats, static_cast<uint32_t>(chunk_indexes_.size()));
  put_u64(&stats, message_count_ ? start_time_ : 0);
  put_u64(&stats, message_count_ ? end_time_ : 0);
  std::string counts;
  for (const auto& [channel, n] : channel_counts_) {
    put_u16(&counts, channel);
    put_u64(&counts, n);
  }
  put_u32(&stats, static_cast<uint32_t>(counts.size()));
  stats += counts;
  add_group(kStatistics, {record(kStatistics, stats)});
  std::vector<std::string> chunk_index_records;
  for (const ChunkIndex& ci : chunk_indexes_) {
    std::string c, offsets;
    put_u64(&c, ci.start_time);
    put_u64(&c, ci.end_time);
    put_u64(&c, ci.offset);
    put_u64(&c, ci.length);
    for (const auto& [channel, offset] : ci.message_index_offsets) {
      put_u16(&offsets, channel);
      put_u64(&offsets, offset);
    }
    put_u32(&c, static_cast<uint32_t>(offsets.size()));
    c += offsets;
    put_u64(&c, ci.message_index_length);
    put_string(&c, "");
    put_u64(&c, ci.size);  // compressed size = uncompressed size (no compression)
    put_u64(&c, ci.size);
    chunk_index_records.push_back(record(kChunkIndex, c));
  }
  add_group(kChunkIndex, chunk_index_records);
  const uint64_t summary_offset_start = summary_start + summary.size();
  for (const Group& g : groups) {
    std::string o;
    put_u8(&o, g.op);
    put_u64(&o, g.start);
    put_u64(&o, g.length);
    summary += record(kSummaryOffset, o);
  }
  std::string footer;
  put_u8(&footer, kFooter);
  put_u64(&footer, 8 + 8 + 4);
  put_u64(&footer, summary_start);
  put_u64(&footer, summary_offset_start);
  summary += footer;
  put_u32(&summary, crc32_update(0, reinterpret_cast<const uint8_t*>(summary.data()), summary.size()));
  write(summary);
  write(std::string(kMagic, 8));
  const bool ok = std::fflush(file_) == 0;
  std::fclose(file_);
  file_ = nullptr;
  if (!ok) throw std::runtime_error(path_ + ": write failed");
}

}  // namespace nadir
