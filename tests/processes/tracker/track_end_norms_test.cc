#include "processes/tracker/track_end_norms.h"

#include <gtest/gtest.h>

#include <vector>

#include "common/config.h"

namespace nadir {
namespace {

CameraModel default_camera() {
  return CameraModel::from_config(Config::load_file(NADIR_SOURCE_DIR "/config/default.yaml"));
}

// Bit-for-bit equality: the cache must not change a single published byte.
void expect_same_bits(const std::vector<cv::Point2d>& a, const std::vector<cv::Point2d>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x) << "point " << i;
    EXPECT_EQ(a[i].y, b[i].y) << "point " << i;
  }
}

TEST(TrackEndNorms, EmptyCacheUndistortsEveryPoint) {
  const CameraModel camera = default_camera();
  const std::vector<cv::Point2f> px = {{10.5f, 20.25f}, {300.f, 250.f}, {600.f, 500.f}};
  const TrackEndNorms norms;
  expect_same_bits(norms.undistort_prev({1, 2, 3}, px, camera), camera.undistort(px));
}

TEST(TrackEndNorms, RememberedEndsAreReusedAndOthersUndistorted) {
  const CameraModel camera = default_camera();
  // Last frame: tracks 2, 4, 7 ended here.
  const std::vector<int64_t> last_ids = {2, 4, 7};
  const std::vector<cv::Point2f> last_px = {{50.f, 60.f}, {200.5f, 100.25f}, {400.f, 450.f}};
  TrackEndNorms norms;
  norms.remember(last_ids, last_px, camera.undistort(last_px));
  // This frame: 1 is new to the cache, 4 and 7 match, 5 is new, and 2's
  // pixel differs (say, after a restart), so it must not be taken over.
  const std::vector<int64_t> ids = {1, 2, 4, 5, 7};
  const std::vector<cv::Point2f> px = {{30.f, 30.f}, {51.f, 60.f}, {200.5f, 100.25f}, {320.f, 240.f}, {400.f, 450.f}};
  expect_same_bits(norms.undistort_prev(ids, px, camera), camera.undistort(px));
}

TEST(TrackEndNorms, RememberReplacesWhatWasKept) {
  const CameraModel camera = default_camera();
  TrackEndNorms norms;
  const std::vector<cv::Point2f> px = {{100.f, 100.f}};
  norms.remember({3}, px, {cv::Point2d(9.0, 9.0)});  // a value undistortion would never give
  norms.remember({}, {}, {});
  expect_same_bits(norms.undistort_prev({3}, px, camera), camera.undistort(px));
}

}  // namespace
}  // namespace nadir
