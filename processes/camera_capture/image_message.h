#pragma once
// Builds an encoded nadir::image_t with exactly one copy of the pixels: the
// header is encoded with an empty data array, the size field (the last field
// before the bytes) is patched, and the caller writes the pixels straight
// into the encoded buffer (memcpy from the Aravis buffer, or a Bayer-to-mono
// conversion). The buffer is reused from frame to frame.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "nadir/image_t.hpp"

namespace nadir {

class ImageMessageEncoder {
 public:
  // Encodes `header` (its data/size are ignored) for `data_size` pixel bytes
  // and returns where the pixels go.
  uint8_t* begin(const image_t& header, size_t data_size);
  const uint8_t* data() const { return buffer_.data(); }
  size_t size() const { return buffer_.size(); }

 private:
  std::vector<uint8_t> buffer_;
  image_t scratch_;
};

}  // namespace nadir
