#include "common/log_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace nadir {
namespace {

constexpr uint32_t kSyncWord = 0xEDA1DA01u;
constexpr uint64_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;
constexpr uint32_t kMaxChannelLength = 256;
constexpr uint32_t kMaxDataLength = 1u << 30;

uint32_t read_u32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
uint64_t read_u64(const uint8_t* p) { return (uint64_t{read_u32(p)} << 32) | read_u32(p + 4); }

void put_u32(uint8_t* p, uint32_t v) {
  p[0] = static_cast<uint8_t>(v >> 24);
  p[1] = static_cast<uint8_t>(v >> 16);
  p[2] = static_cast<uint8_t>(v >> 8);
  p[3] = static_cast<uint8_t>(v);
}
void put_u64(uint8_t* p, uint64_t v) {
  put_u32(p, static_cast<uint32_t>(v >> 32));
  put_u32(p + 4, static_cast<uint32_t>(v));
}

bool printable_channel(const uint8_t* p, uint32_t length) {
  for (uint32_t i = 0; i < length; ++i) {
    if (p[i] < 0x20 || p[i] > 0x7e) return false;
  }
  return true;
}

}  // namespace

LogReader::LogReader(const std::string& path) : path_(path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(path + ": cannot open log: " + std::strerror(errno));
  struct stat info {};
  if (::fstat(fd, &info) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    throw std::runtime_error(path + ": cannot stat log: " + reason);
  }
  size_ = static_cast<uint64_t>(info.st_size);
  if (size_ > 0) {
    void* map = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (map == MAP_FAILED) {
      const std::string reason = std::strerror(errno);
      ::close(fd);
      throw std::runtime_error(path + ": cannot map log: " + reason);
    }
    ::madvise(map, size_, MADV_SEQUENTIAL);
    map_ = static_cast<const uint8_t*>(map);
  }
  ::close(fd);
}

LogReader::~LogReader() {
  if (map_ != nullptr) ::munmap(const_cast<uint8_t*>(map_), size_);
}

bool LogReader::record_fits_at(uint64_t offset, LogEvent* event, std::string* why) const {
  const uint8_t* p = map_ + offset;
  if (read_u32(p) != kSyncWord) {
    *why = "no sync word";
    return false;
  }
  const uint32_t channel_length = read_u32(p + 20);
  const uint32_t data_length = read_u32(p + 24);
  if (channel_length == 0 || channel_length > kMaxChannelLength) {
    *why = "channel length " + std::to_string(channel_length) + " is not in [1, 256]";
    return false;
  }
  if (data_length > kMaxDataLength) {
    *why = "data length " + std::to_string(data_length) + " is implausible";
    return false;
  }
  const uint64_t end = offset + kHeaderBytes + channel_length + data_length;
  if (end > size_) {
    *why = "record runs past the end of the file";
    return false;
  }
  if (!printable_channel(p + kHeaderBytes, channel_length)) {
    *why = "channel name is not printable";
    return false;
  }
  if (end != size_ && (end + 4 > size_ || read_u32(map_ + end) != kSyncWord)) {
    // The next record is damaged, or this one's lengths are. Lengths that
    // reach over the next record's sync word are wrong; otherwise keep this
    // record and let the bytes after it be reported as damage.
    const uint64_t next_sync = find_sync(offset + kHeaderBytes);
    if (next_sync < end) {
      *why = "record lengths reach over the next record (lengths damaged)";
      return false;
    }
  }
  event->event_number = static_cast<int64_t>(read_u64(p + 4));
  event->timestamp = static_cast<int64_t>(read_u64(p + 12));
  event->channel.assign(reinterpret_cast<const char*>(p + kHeaderBytes), channel_length);
  event->data = p + kHeaderBytes + channel_length;
  event->size = data_length;
  event->offset = offset;
  return true;
}

uint64_t LogReader::find_sync(uint64_t from) const {
  for (uint64_t i = from; i + 4 <= size_; ++i) {
    if (map_[i] == 0xED && read_u32(map_ + i) == kSyncWord) return i;
  }
  return size_;
}

bool LogReader::next(LogEvent* event) {
  while (position_ < size_) {
    if (size_ - position_ < kHeaderBytes) {
      truncated_ = true;
      damage_.push_back({position_, size_ - position_, "truncated record header at the end of the file"});
      position_ = size_;
      return false;
    }
    std::string why;
    if (record_fits_at(position_, event, &why)) {
      position_ = position_ + kHeaderBytes + event->channel.size() + event->size;
      return true;
    }
    const uint64_t resume = find_sync(position_ + 1);
    if (resume == size_ && why == "record runs past the end of the file") truncated_ = true;
    damage_.push_back({position_, resume - position_, why});
    position_ = resume;
  }
  return false;
}

std::string LogReader::damage_report() const {
  std::ostringstream out;
  for (const LogDamage& d : damage_) {
    out << path_ << ": byte " << d.offset << ": " << d.what << "; skipped " << d.skipped_bytes << " bytes\n";
  }
  return out.str();
}

LogWriter::LogWriter(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) throw std::runtime_error(path + ": cannot create log: " + std::strerror(errno));
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

LogWriter::~LogWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void LogWriter::write(int64_t timestamp, const std::string& channel, const uint8_t* data, size_t size) {
  uint8_t header[kHeaderBytes];
  put_u32(header, kSyncWord);
  put_u64(header + 4, static_cast<uint64_t>(next_event_++));
  put_u64(header + 12, static_cast<uint64_t>(timestamp));
  put_u32(header + 20, static_cast<uint32_t>(channel.size()));
  put_u32(header + 24, static_cast<uint32_t>(size));
  if (std::fwrite(header, 1, kHeaderBytes, file_) != kHeaderBytes ||
      std::fwrite(channel.data(), 1, channel.size(), file_) != channel.size() ||
      (size > 0 && std::fwrite(data, 1, size, file_) != size)) {
    throw std::runtime_error(path_ + ": write failed: " + std::strerror(errno));
  }
}

void LogWriter::flush() {
  if (std::fflush(file_) != 0) throw std::runtime_error(path_ + ": flush failed: " + std::strerror(errno));
}

}  // namespace nadir
