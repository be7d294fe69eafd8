// LucasKanade against geometry and against cv::calcOpticalFlowPyrLK: the
// same method, so the same tracks (to float rounding) and the same losses.
#include "processes/tracker/lucas_kanade.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
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

// The local linear map from `a`'s pixels to `b`'s: what a window around a
// feature of `a` becomes in `b`.
cv::Matx22f view_warp(const ViewPose& a, const ViewPose& b) {
  const cv::Point2d o = SyntheticScene::map_point({300, 250}, a, b, kFrame);
  const cv::Point2d x = SyntheticScene::map_point({301, 250}, a, b, kFrame) - o;
  const cv::Point2d y = SyntheticScene::map_point({300, 251}, a, b, kFrame) - o;
  return cv::Matx22f(static_cast<float>(x.x), static_cast<float>(y.x), static_cast<float>(x.y),
                     static_cast<float>(y.y));
}

// Median error of the tracks of `pair`'s corners against the scene's own
// mapping, with and without the window warp; `signed_bias` gets the mean
// error along the unit vector from the view's centre (a spurious expansion
// reads as a positive bias).
double median_error(const Pair& pair, const ViewPose& a, const ViewPose& b, const cv::Matx22f* warp,
                    double* signed_bias = nullptr) {
  LucasKanade klt{LkOptions{}};
  std::vector<double> errors;
  double radial = 0;
  for (const cv::Point2f& q : corners(pair.prev_image)) {
    if (q.x < 40 || q.y < 40 || q.x > kFrame.width - 40 || q.y > kFrame.height - 40) continue;
    const cv::Point2d truth = SyntheticScene::map_point(q, a, b, kFrame);
    cv::Point2f next(static_cast<float>(truth.x), static_cast<float>(truth.y));
    if (!klt.track(pair.prev, pair.curr, q, &next, 2, nullptr, warp)) continue;
    const cv::Point2d e(next.x - truth.x, next.y - truth.y);
    errors.push_back(std::hypot(e.x, e.y));
    const cv::Point2d r(truth.x - kFrame.width / 2.0, truth.y - kFrame.height / 2.0);
    radial += (e.x * r.x + e.y * r.y) / std::hypot(r.x, r.y);
  }
  EXPECT_GT(errors.size(), 150u);
  if (signed_bias) *signed_bias = radial / static_cast<double>(errors.size());
  std::sort(errors.begin(), errors.end());
  return errors[errors.size() / 2];
}

// A view turned and moved against the first: each window is a rotated
// square in the second image, which a translation-only KLT cannot match
// exactly. Resampled through the view's own linear map, the template
// matches and the error falls to the interpolation's.
TEST(LucasKanade, AWarpedTemplateFollowsATurnedView) {
  const ViewPose a{{700, 700}, 0.0}, b{{706.3, 695.2}, 0.04};
  const Pair p = make_pair(a, b, 0.0);
  const cv::Matx22f warp = view_warp(a, b);
  EXPECT_NEAR(warp(1, 0), -std::sin(0.04), 1e-6);  // the map is the rotation back by the view's turn
  const double plain = median_error(p, a, b, nullptr);
  const double warped = median_error(p, a, b, &warp);
  RecordProperty("median_error_plain_mpx", static_cast<int>(plain * 1e3));
  RecordProperty("median_error_warped_mpx", static_cast<int>(warped * 1e3));
  EXPECT_GT(plain, 0.03);
  EXPECT_LT(warped, 0.015);
  EXPECT_LT(warped, plain / 3);
  const cv::Matx22f identity = cv::Matx22f::eye();
  EXPECT_NEAR(median_error(p, a, b, &identity), plain, 0.002) << "the identity warp is the plain KLT";
}

TEST(LucasKanade, RefusesAWarpBeyondItsBound) {
  const Pair p = make_pair({{700, 700}, 0.0}, {{700, 700}, 0.0}, 0.0);
  LucasKanade klt{LkOptions{}};
  cv::Point2f next(300, 300);
  const cv::Matx22f too_large(1.0f + 1.01f * LucasKanade::kMaxWarpDeviation, 0.f, 0.f, 1.f);
  EXPECT_THROW(klt.track(p.prev, p.curr, next, &next, 2, nullptr, &too_large), std::invalid_argument);
  const cv::Matx22f nan(std::numeric_limits<float>::quiet_NaN(), 0.f, 0.f, 1.f);
  EXPECT_THROW(klt.track(p.prev, p.curr, next, &next, 2, nullptr, &nan), std::invalid_argument);
  // At the bound, for a window as far outside as the KLT accepts, every read
  // stays inside the pyramid's border (AddressSanitizer checks the build).
  const cv::Matx22f worst(1.f - 0.999f * LucasKanade::kMaxWarpDeviation, 0.999f * LucasKanade::kMaxWarpDeviation,
                          0.999f * LucasKanade::kMaxWarpDeviation, 1.f - 0.999f * LucasKanade::kMaxWarpDeviation);
  for (const cv::Point2f start : {cv::Point2f(-10.4f, -10.4f), cv::Point2f(kFrame.width + 9.4f, kFrame.height + 9.4f)}) {
    next = start;
    klt.track(p.prev, p.curr, start, &next, 0, nullptr, &worst);
  }
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

// An 8-bit texture made with integer arithmetic only (hashed noise, box
// filters, block means), so that the images are the same on every machine:
// the 4x-resolution texture seen through 4x4 block means, moved by `shift_q`
// quarter pixels.
cv::Mat integer_texture_view(cv::Size size, cv::Point shift_q) {
  const int fine_w = (size.width + 8) * 4, fine_h = (size.height + 8) * 4;
  std::vector<int32_t> fine(static_cast<size_t>(fine_w) * static_cast<size_t>(fine_h));
  for (int y = 0; y < fine_h; ++y)
    for (int x = 0; x < fine_w; ++x) {
      uint32_t h = static_cast<uint32_t>(x / 6) * 73856093u ^ static_cast<uint32_t>(y / 6) * 19349663u;
      h ^= h >> 13;
      h *= 0x5bd1e995u;
      h ^= h >> 15;
      fine[static_cast<size_t>(y) * static_cast<size_t>(fine_w) + static_cast<size_t>(x)] =
          static_cast<int32_t>(h & 255u);
    }
  cv::Mat view(size, CV_8UC1);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      int32_t sum = 0;
      for (int dy = 0; dy < 12; ++dy)
        for (int dx = 0; dx < 12; ++dx)
          sum += fine[static_cast<size_t>(y * 4 + 16 + shift_q.y + dy) * static_cast<size_t>(fine_w) +
                      static_cast<size_t>(x * 4 + 16 + shift_q.x + dx)];
      view.at<uint8_t>(y, x) = static_cast<uint8_t>(sum / 144);
    }
  return view;
}

// The same bits on every machine: a digest of every output bit of a fixed
// job. CI runs these in the normal build (on x86-64 with AVX2 the cloned
// loops and the warped sampling run on AVX2) and in the sanitizer build (no
// clones, the scalar sampling: SSE2), so both code paths are held to the
// recorded values.
struct DigestJob {
  uint64_t digest = 1469598103934665603ull;  // FNV-1a
  int tracked = 0;
  double worst = 0;  // px from the true shift, away from the borders
};

// Every eighth pixel of a 160 x 128 texture tracked into its shifted view and
// back, the forward template resampled through `warp` when given.
DigestJob track_digest_job(const cv::Matx22f* warp) {
  const cv::Size size(160, 128);
  const cv::Mat a = integer_texture_view(size, {0, 0});
  const cv::Mat b = integer_texture_view(size, {7, -5});  // (1.75, -1.25) px
  LkPyramid prev, curr;
  prev.build(a, 3, LucasKanade::border_for(21));
  curr.build(b, 3, LucasKanade::border_for(21));
  LucasKanade forward{LkOptions{}};
  LkOptions back_options;
  back_options.window_px = 8;
  LucasKanade backward{back_options};
  DigestJob job;
  auto mix = [&job](const void* data, size_t n) {
    for (size_t i = 0; i < n; ++i) job.digest = (job.digest ^ static_cast<const uint8_t*>(data)[i]) * 1099511628211ull;
  };
  for (int y = 4; y < size.height; y += 8)
    for (int x = 4; x < size.width; x += 8) {
      const cv::Point2f p(static_cast<float>(x) + 0.3f, static_cast<float>(y) + 0.6f);
      cv::Point2f next = p, back = p;
      float error = 0.f;
      const uint8_t ok = forward.track(prev, curr, p, &next, 2, &error, warp);
      const uint8_t ok_back = backward.track(curr, prev, next, &back, 1, nullptr);
      mix(&ok, 1);
      mix(&ok_back, 1);
      mix(&next, sizeof next);
      mix(&back, sizeof back);
      mix(&error, sizeof error);
      if (ok && x > 24 && y > 24 && x < size.width - 24 && y < size.height - 24) {
        ++job.tracked;
        job.worst = std::max(job.worst, static_cast<double>(cv::norm(next - p - cv::Point2f(-1.75f, 1.25f))));
      }
    }
  return job;
}

TEST(LucasKanade, OutputBitsMatchTheRecordedDigest) {
  const DigestJob job = track_digest_job(nullptr);
  EXPECT_GT(job.tracked, 100);
  EXPECT_LT(job.worst, 0.2);  // a sane job: block means are not an exact shift
  EXPECT_EQ(job.digest, 0x9f35d96e70d220f1ull) << std::hex << "digest 0x" << job.digest;
}

TEST(LucasKanade, WarpedTemplateOutputBitsMatchTheRecordedDigest) {
  // A warp a little off the true one (identity: the views differ by a shift),
  // so that every sample of the warped template falls between pixels.
  const cv::Matx22f warp(1.015f, 0.02f, -0.025f, 0.99f);
  const DigestJob job = track_digest_job(&warp);
  EXPECT_GT(job.tracked, 100);
  EXPECT_LT(job.worst, 0.5);
  EXPECT_EQ(job.digest, 0xfffca6a0ad4e6d93ull) << std::hex << "digest 0x" << job.digest;
}

}  // namespace
}  // namespace nadir
