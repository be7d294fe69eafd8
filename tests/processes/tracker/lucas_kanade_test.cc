// LucasKanade against geometry and against cv::calcOpticalFlowPyrLK: the
// same method, so the same tracks (to float rounding) and the same losses.
#include "processes/tracker/lucas_kanade.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "synthetic_scene.h"

namespace nadir {
namespace {

using testing::SyntheticScene;
using testing::ViewPose;

const cv::Size kFrame(612, 512);

const SyntheticScene& scene() {
  static const SyntheticScene s(cv::Size(1400, 1400), 7);
  return s;
}

std::vector<cv::Point2f> corners(const cv::Mat& image) {
  std::vector<cv::Point2f> pts;
  cv::goodFeaturesToTrack(image, pts, 300, 0.01, 12, cv::noArray(), 3, true, 0.04);
  return pts;
}

struct Pair {
  LkPyramid prev, curr;
  cv::Mat prev_image, curr_image;
};

Pair make_pair(const ViewPose& a, const ViewPose& b, double noise, int levels = 3) {
  Pair p;
  p.prev_image = scene().render(a, kFrame, noise, 1);
  p.curr_image = scene().render(b, kFrame, noise, 2);
  p.prev.build(p.prev_image, levels, LucasKanade::border_for(21));
  p.curr.build(p.curr_image, levels, LucasKanade::border_for(21));
  return p;
}

TEST(LucasKanade, RecoversANoiseFreeSubPixelShiftThroughThePyramid) {
  const ViewPose a{{700, 700}, 0.0}, b{{705.37, 691.81}, 0.0};
  Pair p = make_pair(a, b, 0.0);
  LucasKanade klt{LkOptions{}};
  int tracked = 0;
  std::vector<double> errors;
  for (const cv::Point2f& q : corners(p.prev_image)) {
    if (q.x < 40 || q.y < 40 || q.x > kFrame.width - 40 || q.y > kFrame.height - 40) continue;
    cv::Point2f next = q;
    float error = -1.f;
    if (!klt.track(p.prev, p.curr, q, &next, 2, &error)) continue;
    ++tracked;
    const cv::Point2d truth = SyntheticScene::map_point(q, a, b, kFrame);
    errors.push_back(std::hypot(next.x - truth.x, next.y - truth.y));
    EXPECT_GE(error, 0.f);
    EXPECT_LT(error, 2.f);  // the same texture, resampled: a small patch error
  }
  ASSERT_GT(tracked, 200);
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.02);
  EXPECT_LT(errors[errors.size() * 95 / 100], 0.06);
}

TEST(LucasKanade, AgreesWithOpenCvsPyramidalKlt) {
  const ViewPose a{{650, 720}, 0.0}, b{{653.1, 718.7}, 0.004};
  Pair p = make_pair(a, b, 1.5);
  const std::vector<cv::Point2f> pts = corners(p.prev_image);
  std::vector<cv::Point2f> cv_next;
  std::vector<uchar> cv_status;
  std::vector<float> cv_error;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  cv::calcOpticalFlowPyrLK(p.prev_image, p.curr_image, pts, cv_next, cv_status, cv_error, cv::Size(21, 21), 2,
                           criteria, 0, 1e-4);
  LucasKanade klt{LkOptions{}};
  int both = 0, disagree = 0;
  double max_diff = 0, max_error_diff = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    // Where the window overlaps the image edge the two differ by design:
    // OpenCV pads its derivative images with zeros, this class takes the
    // gradients of the mirrored border. The tracker keeps tracks 10 px in.
    const cv::Point2f& q = pts[i];
    if (q.x < 12 || q.y < 12 || q.x > kFrame.width - 13 || q.y > kFrame.height - 13) continue;
    cv::Point2f next = pts[i];
    float error = 0.f;
    const bool ok = klt.track(p.prev, p.curr, pts[i], &next, 2, &error);
    if (ok != static_cast<bool>(cv_status[i])) {
      ++disagree;
      continue;
    }
    if (!ok) continue;
    ++both;
    max_diff = std::max(max_diff, static_cast<double>(cv::norm(next - cv_next[i])));
    max_error_diff = std::max(max_error_diff, std::fabs(static_cast<double>(error - cv_error[i])));
  }
  EXPECT_GT(both, 250);
  EXPECT_LE(disagree, 2);
  // OpenCV interpolates in 14-bit fixed point; the two stop within the
  // 0.01 px step criterion of each other.
  EXPECT_LT(max_diff, 0.05);
  EXPECT_LT(max_error_diff, 0.1);
}

TEST(LucasKanade, LosesAFlatPatchAndAWindowOutsideTheImage) {
  cv::Mat flat(kFrame, CV_8UC1, cv::Scalar(120));
  cv::rectangle(flat, cv::Rect(300, 200, 80, 80), cv::Scalar(200), cv::FILLED);
  LkPyramid prev, curr;
  prev.build(flat, 3, LucasKanade::border_for(21));
  curr.build(flat, 3, LucasKanade::border_for(21));
  LucasKanade klt{LkOptions{}};
  cv::Point2f next(100, 100);
  EXPECT_FALSE(klt.track(prev, curr, cv::Point2f(100, 100), &next, 2, nullptr)) << "no texture at all";
  next = cv::Point2f(300, 200);
  EXPECT_TRUE(klt.track(prev, curr, cv::Point2f(300, 200), &next, 2, nullptr)) << "a corner of the square";
  EXPECT_LT(cv::norm(next - cv::Point2f(300, 200)), 0.01);

  Pair p = make_pair({{700, 700}, 0.0}, {{700, 700}, 0.0}, 0.0);
  for (const cv::Point2f start : {cv::Point2f(-40, 100), cv::Point2f(100, 560), cv::Point2f(1e9f, 5),
                                  cv::Point2f(std::numeric_limits<float>::quiet_NaN(), 5)}) {
    next = start;
    EXPECT_FALSE(klt.track(p.prev, p.curr, cv::Point2f(300, 300), &next, 0, nullptr))
        << "start " << start.x << "," << start.y;
  }
}

TEST(LucasKanade, RefusesPyramidsItCannotUse) {
  Pair p = make_pair({{700, 700}, 0.0}, {{701, 700}, 0.0}, 0.0, 2);
  LucasKanade klt{LkOptions{}};
  cv::Point2f next(300, 300);
  EXPECT_THROW(klt.track(p.prev, p.curr, next, &next, 2, nullptr), std::invalid_argument);
  LkPyramid narrow;
  narrow.build(p.curr_image, 2, 4);
  EXPECT_THROW(klt.track(p.prev, narrow, next, &next, 1, nullptr), std::invalid_argument);
  LkOptions tiny;
  tiny.window_px = 2;
  EXPECT_THROW(LucasKanade{tiny}, std::invalid_argument);
}

// No state carries over from one point to the next: tracking the points in
// reverse order with another instance gives the same bits.
TEST(LucasKanade, EachPointsResultIsIndependentOfTheOthers) {
  Pair p = make_pair({{640, 700}, 0.0}, {{642.6, 699.1}, 0.002}, 1.5);
  const std::vector<cv::Point2f> pts = corners(p.prev_image);
  LucasKanade one{LkOptions{}}, two{LkOptions{}};
  std::vector<cv::Point2f> a(pts), b(pts);
  std::vector<float> ea(pts.size()), eb(pts.size());
  std::vector<int> oka(pts.size()), okb(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) oka[i] = one.track(p.prev, p.curr, pts[i], &a[i], 2, &ea[i]);
  for (size_t i = pts.size(); i-- > 0;) okb[i] = two.track(p.prev, p.curr, pts[i], &b[i], 2, &eb[i]);
  EXPECT_EQ(oka, okb);
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]), 0);
  EXPECT_EQ(std::memcmp(ea.data(), eb.data(), ea.size() * sizeof ea[0]), 0);
}

}  // namespace
}  // namespace nadir
