#include "synthetic_scene.h"

#include <opencv2/imgproc.hpp>

#include <cmath>

namespace nadir::testing {

namespace {

// 2x3 matrix taking frame pixels to texture pixels.
cv::Matx23d frame_to_texture(const ViewPose& pose, cv::Size frame_size) {
  const double c = std::cos(pose.angle_rad), s = std::sin(pose.angle_rad);
  const double ux = (frame_size.width - 1) / 2.0, uy = (frame_size.height - 1) / 2.0;
  return {c, -s, pose.centre.x - (c * ux - s * uy), s, c, pose.centre.y - (s * ux + c * uy)};
}

}  // namespace

SyntheticScene::SyntheticScene(cv::Size size, uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat accum(size, CV_32F, cv::Scalar(0));
  // Noise at several scales: fine grain (rocks, crops) to coarse (relief shading).
  const double scales[] = {1.5, 4.0, 12.0};
  const double weights[] = {0.8, 1.0, 0.7};
  for (int i = 0; i < 3; ++i) {
    cv::Mat noise(size, CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
    cv::GaussianBlur(noise, noise, cv::Size(), scales[i]);
    cv::Scalar mean, stddev;
    cv::meanStdDev(noise, mean, stddev);
    accum += noise * (weights[i] / stddev[0]);
  }
  // Field-like patches with sharp borders give strong corners, as real ground does.
  cv::Mat fields(size, CV_32F, cv::Scalar(0));
  const int patches = size.area() / 4000;
  for (int i = 0; i < patches; ++i) {
    const cv::Point corner(rng.uniform(0, size.width), rng.uniform(0, size.height));
    const cv::Size extent(rng.uniform(10, 60), rng.uniform(10, 60));
    cv::rectangle(fields, cv::Rect(corner, extent), cv::Scalar(rng.uniform(-1.5, 1.5)), cv::FILLED);
  }
  accum += fields;
  // Band-limit the whole texture (as a lens does) so that views at any
  // sub-pixel offset are faithful samples of the same continuous image.
  cv::GaussianBlur(accum, accum, cv::Size(), 1.0);
  accum.convertTo(texture_, CV_8U, 30.0, 128.0);
}

cv::Mat SyntheticScene::render(const ViewPose& pose, cv::Size frame_size, double noise_sigma,
                               uint64_t noise_seed) const {
  cv::Mat frame;
  cv::warpAffine(texture_, frame, frame_to_texture(pose, frame_size), frame_size,
                 cv::INTER_LANCZOS4 | cv::WARP_INVERSE_MAP, cv::BORDER_REFLECT_101);
  if (noise_sigma > 0.0) {
    cv::RNG rng(noise_seed);
    cv::Mat noise(frame_size, CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, noise_sigma);
    cv::Mat noisy;
    frame.convertTo(noisy, CV_32F);
    noisy += noise;
    noisy.convertTo(frame, CV_8U);
  }
  return frame;
}

cv::Point2d SyntheticScene::map_point(const cv::Point2d& p, const ViewPose& from, const ViewPose& to,
                                      cv::Size frame_size) {
  const cv::Matx23d a = frame_to_texture(from, frame_size);
  const cv::Point2d world(a(0, 0) * p.x + a(0, 1) * p.y + a(0, 2), a(1, 0) * p.x + a(1, 1) * p.y + a(1, 2));
  cv::Matx23d b_inv;
  cv::invertAffineTransform(frame_to_texture(to, frame_size), b_inv);
  return {b_inv(0, 0) * world.x + b_inv(0, 1) * world.y + b_inv(0, 2),
          b_inv(1, 0) * world.x + b_inv(1, 1) * world.y + b_inv(1, 2)};
}

image_t make_image_msg(const cv::Mat& pixels, int64_t utime, int64_t frame_counter) {
  image_t msg{};
  msg.utime = utime;
  msg.trigger_utime = utime;
  msg.frame_counter = frame_counter;
  msg.trigger_sequence = frame_counter;
  msg.width = pixels.cols;
  msg.height = pixels.rows;
  msg.stride = pixels.cols;
  msg.pixel_format = image_t::PIXEL_MONO8;
  msg.time_quality = image_t::TIME_SIMULATED;
  msg.exposure_us = 2000.0f;
  msg.gain_db = 0.0f;
  msg.data.resize(static_cast<size_t>(pixels.total()));
  for (int y = 0; y < pixels.rows; ++y) {
    const uint8_t* row = pixels.ptr<uint8_t>(y);
    std::copy(row, row + pixels.cols, msg.data.begin() + static_cast<long>(y) * pixels.cols);
  }
  msg.size = static_cast<int32_t>(msg.data.size());
  return msg;
}

}  // namespace nadir::testing
