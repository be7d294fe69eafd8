#include "processes/tracker/image_input.h"

#include <gtest/gtest.h>

#include "synthetic_scene.h"

namespace nadir {
namespace {

using testing::make_image_msg;

image_t mono16_msg(int width, int height, uint16_t value) {
  image_t msg{};
  msg.width = width;
  msg.height = height;
  msg.stride = 2 * width;
  msg.pixel_format = image_t::PIXEL_MONO16;
  msg.data.resize(static_cast<size_t>(msg.stride * height));
  for (size_t i = 0; i < msg.data.size(); i += 2) {
    msg.data[i] = static_cast<uint8_t>(value & 0xff);  // little-endian
    msg.data[i + 1] = static_cast<uint8_t>(value >> 8);
  }
  msg.size = static_cast<int32_t>(msg.data.size());
  return msg;
}

TEST(ImageFormat, AcceptsMono8AndMono16OfTheConfiguredSize) {
  EXPECT_TRUE(check_image_format(make_image_msg(cv::Mat(512, 612, CV_8UC1, cv::Scalar(3)), 1, 1), 612, 512).ok);
  EXPECT_TRUE(check_image_format(mono16_msg(612, 512, 1000), 612, 512).ok);
}

TEST(ImageFormat, NamesWhatIsWrong) {
  const ImageFormatCheck size = check_image_format(make_image_msg(cv::Mat(480, 640, CV_8UC1), 1, 1), 612, 512);
  EXPECT_FALSE(size.ok);
  EXPECT_NE(size.reason.find("640x480"), std::string::npos) << size.reason;

  image_t rgb = make_image_msg(cv::Mat(512, 612, CV_8UC1), 1, 1);
  rgb.pixel_format = 7;
  const ImageFormatCheck format = check_image_format(rgb, 612, 512);
  EXPECT_FALSE(format.ok);
  EXPECT_NE(format.reason.find("pixel_format 7"), std::string::npos) << format.reason;

  image_t short_data = make_image_msg(cv::Mat(512, 612, CV_8UC1), 1, 1);
  short_data.data.resize(1000);
  short_data.size = 1000;
  EXPECT_FALSE(check_image_format(short_data, 612, 512).ok);

  image_t short_stride = make_image_msg(cv::Mat(512, 612, CV_8UC1), 1, 1);
  short_stride.stride = 600;
  EXPECT_NE(check_image_format(short_stride, 612, 512).reason.find("stride 600"), std::string::npos);

  // Mono16 data of Mono8 length is short by half.
  image_t half = mono16_msg(612, 512, 0);
  half.data.resize(612 * 512);
  half.size = 612 * 512;
  EXPECT_FALSE(check_image_format(half, 612, 512).ok);
}

TEST(ImageConversion, Mono16KeepsTheTopSignificantBits) {
  cv::Mat buffer;
  const image_t full = mono16_msg(32, 16, 0xABCD);
  EXPECT_EQ(to_gray8(full, 16, buffer).at<uint8_t>(3, 5), 0xAB);
  const image_t twelve_bit = mono16_msg(32, 16, 0x0ABC);  // 12-bit camera in 16-bit words
  EXPECT_EQ(to_gray8(twelve_bit, 12, buffer).at<uint8_t>(0, 0), 0xAB);
  const image_t overflow = mono16_msg(32, 16, 0xFFFF);  // noise above the declared depth clips
  EXPECT_EQ(to_gray8(overflow, 12, buffer).at<uint8_t>(0, 0), 255);
}

TEST(ImageConversion, Mono8HonoursTheStride) {
  cv::Mat pixels(16, 32, CV_8UC1);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) pixels.at<uint8_t>(y, x) = static_cast<uint8_t>(y * 10 + x);
  image_t msg = make_image_msg(pixels, 1, 1);
  // Re-pack with 8 bytes of padding per row.
  std::vector<uint8_t> padded;
  for (int y = 0; y < 16; ++y) {
    padded.insert(padded.end(), msg.data.begin() + y * 32, msg.data.begin() + (y + 1) * 32);
    padded.insert(padded.end(), 8, 0xEE);
  }
  msg.data = padded;
  msg.stride = 40;
  msg.size = static_cast<int32_t>(padded.size());
  ASSERT_TRUE(check_image_format(msg, 32, 16).ok);
  cv::Mat buffer;
  const cv::Mat gray = to_gray8(msg, 16, buffer);
  EXPECT_EQ(cv::norm(gray, pixels, cv::NORM_INF), 0.0);
}

TEST(ImageQuality, BlackSaturatedFeaturelessAndGood) {
  const TrackerOptions o;
  EXPECT_EQ(check_image_quality(cv::Mat(512, 612, CV_8UC1, cv::Scalar(0)), o).quality, ImageQuality::kBlack);
  EXPECT_EQ(check_image_quality(cv::Mat(512, 612, CV_8UC1, cv::Scalar(255)), o).quality, ImageQuality::kSaturated);
  cv::Mat flat(512, 612, CV_8UC1, cv::Scalar(128));
  cv::RNG rng(3);
  cv::Mat noise(512, 612, CV_8UC1);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 2);  // +-1 grey level of sensor noise, nothing to track
  flat += noise;
  const ImageQualityCheck featureless = check_image_quality(flat, o);
  EXPECT_EQ(featureless.quality, ImageQuality::kFeatureless);
  EXPECT_NE(featureless.reason.find("featureless"), std::string::npos);

  const testing::SyntheticScene scene(cv::Size(612, 512), 5);
  const ImageQualityCheck good = check_image_quality(scene.texture(), o);
  EXPECT_EQ(good.quality, ImageQuality::kGood) << good.reason;
  EXPECT_TRUE(good.reason.empty());
}

TEST(ImageQuality, StatisticsCountEveryPixelOfAnOddWidthView) {
  // 7 columns: the counting loop's tail; a view into a wider image: the stride.
  cv::Mat parent(4, 10, CV_8UC1, cv::Scalar(99));
  cv::Mat view = parent(cv::Rect(1, 0, 7, 4));
  view.setTo(0);
  view.row(0).setTo(255);          // 7 saturated
  view(cv::Rect(6, 1, 1, 3)).setTo(100);  // 3 in the last column
  const ImageQualityCheck check = check_image_quality(view, TrackerOptions{});
  EXPECT_DOUBLE_EQ(check.saturated_fraction, 7.0 / 28.0);
  EXPECT_DOUBLE_EQ(check.dark_fraction, 18.0 / 28.0);
  EXPECT_DOUBLE_EQ(check.mean, (7.0 * 255 + 3.0 * 100) / 28.0);
}

}  // namespace
}  // namespace nadir
