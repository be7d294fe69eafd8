#pragma once
// An MCAP writer (https://mcap.dev/spec, format version 0), written from the
// specification: magic, Header, a data section of chunks (uncompressed), each
// followed by its Message Index records, Data End with the data section's
// CRC32, then a summary section (Schema, Channel, Statistics, Chunk Index
// records), Summary Offset records and the Footer with the summary's CRC32.
// Readers can seek by time through the chunk indexes or stream the file.

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace nadir {

struct McapWriterOptions {
  std::string profile;             // "" : no ROS profile
  std::string library = "nadir";
  size_t chunk_size = 1u << 20;    // a chunk is closed once its records exceed this (bytes)
};

class McapWriter {
 public:
  // Throws std::runtime_error naming the file when it cannot be created.
  McapWriter(const std::string& path, const McapWriterOptions& options);
  ~McapWriter();  // closes (if close() was not called), never throws
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Ids start at 1 (schema id 0 means "no schema").
  uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  uint16_t add_channel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                       const std::map<std::string, std::string>& metadata);
  // Times in nanoseconds.
  void write_message(uint16_t channel_id, uint32_t sequence, uint64_t log_time, uint64_t publish_time,
                     const uint8_t* data, size_t size);
  // Writes the last chunk, the summary and the footer; throws
  // std::runtime_error naming the file when writing failed.
  void close();

  uint64_t message_count() const { return message_count_; }
  uint32_t chunk_count() const { return static_cast<uint32_t>(chunk_indexes_.size()); }

 private:
  struct ChunkIndex {
    uint64_t start_time, end_time, offset, length, message_index_length, size;
    std::map<uint16_t, uint64_t> message_index_offsets;
  };
  void write(const std::string& bytes);
  void flush_chunk();

  std::string path_;
  McapWriterOptions options_;
  std::FILE* file_ = nullptr;
  bool closed_ = false;
  uint64_t position_ = 0;
  bool in_data_section_ = true;  // until Data End
  uint32_t data_crc_ = 0;        // running CRC32 of the data section (from the magic on)
  std::vector<std::string> schema_records_, channel_records_;
  // The open chunk: its records, per channel its (log time, offset) pairs.
  std::string chunk_;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;
  uint64_t chunk_start_ = UINT64_MAX, chunk_end_ = 0;
  std::vector<ChunkIndex> chunk_indexes_;
  std::map<uint16_t, uint64_t> channel_counts_;
  uint64_t message_count_ = 0, start_time_ = UINT64_MAX, end_time_ = 0;
};

// CRC-32 (IEEE 802.3, as zlib's crc32) of `size` bytes continuing from `crc`.
uint32_t crc32_update(uint32_t crc, const uint8_t* data, size_t size);

}  // namespace nadir
