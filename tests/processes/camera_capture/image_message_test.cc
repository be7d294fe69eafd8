// The one-copy image_t encoder must produce exactly what LCM's generated
// encoder produces, so every subscriber decodes it.

#include "processes/camera_capture/image_message.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

namespace nadir {
namespace {

image_t make_header() {
  image_t h{};
  h.utime = 1'700'000'000'123'456;
  h.trigger_utime = 1'700'000'000'122'000;
  h.frame_counter = 4242;
  h.trigger_sequence = 17;
  h.width = 61;
  h.height = 5;
  h.stride = 61;
  h.pixel_format = image_t::PIXEL_MONO8;
  h.time_quality = image_t::TIME_TRIGGER;
  h.exposure_us = 2000.5f;
  h.gain_db = 3.25f;
  return h;
}

TEST(ImageMessage, OneCopyEncodingEqualsGeneratedEncoding) {
  image_t reference = make_header();
  std::vector<uint8_t> pixels(61 * 5);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint8_t>(i * 7 + 3);
  reference.size = static_cast<int32_t>(pixels.size());
  reference.data = pixels;
  std::vector<uint8_t> expected(static_cast<size_t>(reference.getEncodedSize()));
  reference.encode(expected.data(), 0, static_cast<int>(expected.size()));

  ImageMessageEncoder encoder;
  uint8_t* out = encoder.begin(make_header(), pixels.size());
  std::memcpy(out, pixels.data(), pixels.size());
  ASSERT_EQ(encoder.size(), expected.size());
  EXPECT_EQ(0, std::memcmp(encoder.data(), expected.data(), expected.size()));

  image_t decoded;
  ASSERT_EQ(decoded.decode(encoder.data(), 0, static_cast<int>(encoder.size())), static_cast<int>(encoder.size()));
  EXPECT_EQ(decoded.frame_counter, 4242);
  EXPECT_EQ(decoded.trigger_sequence, 17);
  EXPECT_EQ(decoded.data, pixels);
}

TEST(ImageMessage, BufferIsReusedAcrossSizes) {
  ImageMessageEncoder encoder;
  image_t h = make_header();
  std::memset(encoder.begin(h, 1000), 0xAB, 1000);
  const size_t big = encoder.size();
  h.width = 10;
  h.height = 10;
  h.stride = 10;
  std::memset(encoder.begin(h, 100), 0x11, 100);
  EXPECT_EQ(encoder.size(), big - 900);
  image_t decoded;
  ASSERT_EQ(decoded.decode(encoder.data(), 0, static_cast<int>(encoder.size())), static_cast<int>(encoder.size()));
  EXPECT_EQ(decoded.size, 100);
  EXPECT_EQ(decoded.data[99], 0x11);
}

}  // namespace
}  // namespace nadir
