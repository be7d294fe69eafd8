// Frame sources of the fake camera: the pattern, and CAMERA_IMAGE frames
// read from an LCM log (what the simulator writes), cropped/padded to the
// camera's region, damaged or foreign records skipped.

#include "processes/camera_capture/frame_source.h"

#include <gtest/gtest.h>

#include <vector>

#include "common/log_file.h"
#include "nadir/image_t.hpp"
#include "tests/common/test_support.h"

namespace nadir {
namespace {

void write_image(LogWriter& log, int width, int height, uint8_t base, int8_t format = image_t::PIXEL_MONO8) {
  image_t m{};
  m.width = width;
  m.height = height;
  const int bpp = format == image_t::PIXEL_MONO16 ? 2 : 1;
  m.stride = width * bpp;
  m.pixel_format = format;
  m.size = m.stride * height;
  m.data.resize(static_cast<size_t>(m.size));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const uint8_t v = static_cast<uint8_t>(base + x + 10 * y);
      if (bpp == 1) {
        m.data[static_cast<size_t>(y * m.stride + x)] = v;
      } else {
        m.data[static_cast<size_t>(y * m.stride + 2 * x)] = 0x55;  // low byte
        m.data[static_cast<size_t>(y * m.stride + 2 * x + 1)] = v;
      }
    }
  }
  std::vector<uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  log.write(0, "CAMERA_IMAGE", bytes.data(), bytes.size());
}

TEST(FrameSource, PatternIsWhatTestsCheck) {
  PatternFrameSource source;
  std::vector<uint8_t> pixels(20 * 4);
  source.fill(7, 20, 4, 20, pixels.data());
  EXPECT_EQ(pixels[0], PatternFrameSource::value(0, 0, 7));
  EXPECT_EQ(pixels[3 * 20 + 19], static_cast<uint8_t>(19 + 6 + 21));
}

TEST(FrameSource, LogFramesAreServedInOrderCroppedPaddedAndLooped) {
  testing::TempDir dir("frame_source");
  const std::string path = dir.file("sim.lcmlog");
  {
    LogWriter log(path);
    write_image(log, 8, 4, 0);
    const uint8_t junk[5] = {1, 2, 3, 4, 5};
    log.write(0, "CAMERA_IMAGE", junk, sizeof(junk));  // undecodable: skipped
    log.write(0, "INS", junk, sizeof(junk));            // other channel: ignored
    write_image(log, 4, 2, 100, image_t::PIXEL_MONO16);
  }
  LogFrameSource source(path, "CAMERA_IMAGE", 100);
  EXPECT_EQ(source.frames(), 2u);
  EXPECT_EQ(source.skipped(), 1);
  std::vector<uint8_t> pixels(6 * 3, 0xEE);
  source.fill(0, 6, 3, 6, pixels.data());  // 8x4 frame cropped to 6x3
  EXPECT_EQ(pixels[0], 0);
  EXPECT_EQ(pixels[5], 5);
  EXPECT_EQ(pixels[2 * 6 + 1], 21);
  source.fill(1, 6, 3, 6, pixels.data());  // 4x2 Mono16 frame padded with black
  EXPECT_EQ(pixels[0], 100);               // high byte
  EXPECT_EQ(pixels[3], 103);
  EXPECT_EQ(pixels[4], 0);
  EXPECT_EQ(pixels[1 * 6 + 2], 112);
  EXPECT_EQ(pixels[2 * 6 + 0], 0);
  source.fill(2, 6, 3, 6, pixels.data());  // loops to the first frame
  EXPECT_EQ(pixels[5], 5);
}

TEST(FrameSource, LogWithoutImagesIsAClearError) {
  testing::TempDir dir("frame_source_empty");
  const std::string path = dir.file("empty.lcmlog");
  {
    LogWriter log(path);
    const uint8_t junk[5] = {1, 2, 3, 4, 5};
    log.write(0, "INS", junk, sizeof(junk));
  }
  try {
    LogFrameSource source(path, "CAMERA_IMAGE", 10);
    FAIL() << "accepted a log without images";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("CAMERA_IMAGE"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nadir
