#include "processes/camera_capture/frame_source.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "common/log_file.h"
#include "common/message_guard.h"
#include "nadir/image_t.hpp"

namespace nadir {

void PatternFrameSource::fill(uint64_t frame_id, int width, int height, size_t stride, uint8_t* pixels) {
  for (int y = 0; y < height; ++y) {
    uint8_t* row = pixels + static_cast<size_t>(y) * stride;
    for (int x = 0; x < width; ++x) row[x] = value(x, y, frame_id);
  }
}

LogFrameSource::LogFrameSource(const std::string& path, const std::string& channel, size_t max_frames)
    : path_(path) {
  LogReader reader(path);
  LogEvent event;
  image_t image;
  while (frames_.size() < max_frames && reader.next(&event)) {
    if (event.channel != channel) continue;
    std::string reason;
    const bool decoded = decode_message(event.data, event.size, &image, &reason);
    const bool mono8 = image.pixel_format == image_t::PIXEL_MONO8;
    const bool mono16 = image.pixel_format == image_t::PIXEL_MONO16;
    const size_t bpp = mono16 ? 2 : 1;
    if (!decoded || (!mono8 && !mono16) || image.width <= 0 || image.height <= 0 ||
        image.stride < image.width * static_cast<int>(bpp) ||
        static_cast<size_t>(image.size) < static_cast<size_t>(image.stride) * (image.height - 1) + image.width * bpp) {
      ++skipped_;
      continue;
    }
    Frame frame;
    frame.width = image.width;
    frame.height = image.height;
    frame.utime = image.utime;
    frame.mono8.resize(static_cast<size_t>(image.width) * image.height);
    for (int y = 0; y < image.height; ++y) {
      const uint8_t* row = image.data.data() + static_cast<size_t>(y) * image.stride;
      uint8_t* out = frame.mono8.data() + static_cast<size_t>(y) * image.width;
      if (mono8) {
        std::memcpy(out, row, static_cast<size_t>(image.width));
      } else {
        for (int x = 0; x < image.width; ++x) out[x] = row[2 * x + 1];  // little-endian high byte
      }
    }
    frames_.push_back(std::move(frame));
  }
  if (frames_.empty()) {
    throw std::runtime_error(path + ": no usable " + channel + " frame (Mono8/Mono16 image_t); " +
                             std::to_string(skipped_) + " skipped, " + std::to_string(reader.corrupt_records()) +
                             " damaged records");
  }
}

void LogFrameSource::fill(uint64_t, int width, int height, size_t stride, uint8_t* pixels) {
  const int64_t selected = selected_.load();
  const Frame& frame = selected >= 0 ? frames_[static_cast<size_t>(selected)] : frames_[served_++ % frames_.size()];
  for (int y = 0; y < height; ++y) {
    uint8_t* row = pixels + static_cast<size_t>(y) * stride;
    const int copy = y < frame.height ? std::min(width, frame.width) : 0;
    if (copy > 0) std::memcpy(row, frame.mono8.data() + static_cast<size_t>(y) * frame.width, static_cast<size_t>(copy));
    std::memset(row + copy, 0, static_cast<size_t>(width - copy));
  }
}

std::string LogFrameSource::describe() const {
  return "log " + path_ + " (" + std::to_string(frames_.size()) + " frames, looping)";
}

}  // namespace nadir
