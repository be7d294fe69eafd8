#include "processes/camera_capture/image_message.h"

#include <limits>
#include <stdexcept>

namespace nadir {

uint8_t* ImageMessageEncoder::begin(const image_t& header, size_t data_size) {
  if (data_size > static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
    throw std::runtime_error("image of " + std::to_string(data_size) + " bytes does not fit an image_t");
  }
  // Copy the header fields only; the pixel vector stays empty.
  scratch_.utime = header.utime;
  scratch_.trigger_utime = header.trigger_utime;
  scratch_.frame_counter = header.frame_counter;
  scratch_.trigger_sequence = header.trigger_sequence;
  scratch_.width = header.width;
  scratch_.height = header.height;
  scratch_.stride = header.stride;
  scratch_.pixel_format = header.pixel_format;
  scratch_.time_quality = header.time_quality;
  scratch_.exposure_us = header.exposure_us;
  scratch_.gain_db = header.gain_db;
  scratch_.size = 0;
  scratch_.data.clear();
  const int header_size = scratch_.getEncodedSize();
  buffer_.resize(static_cast<size_t>(header_size) + data_size);
  if (scratch_.encode(buffer_.data(), 0, header_size) != header_size) {
    throw std::runtime_error("image_t header encoding failed");
  }
  // The int32 size field (big-endian) ends the header.
  const uint32_t n = static_cast<uint32_t>(data_size);
  uint8_t* size_field = buffer_.data() + header_size - 4;
  size_field[0] = static_cast<uint8_t>(n >> 24);
  size_field[1] = static_cast<uint8_t>(n >> 16);
  size_field[2] = static_cast<uint8_t>(n >> 8);
  size_field[3] = static_cast<uint8_t>(n);
  return buffer_.data() + header_size;
}

}  // namespace nadir
