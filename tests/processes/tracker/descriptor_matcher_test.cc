// The descriptor matcher on generated texture seen through known homographies:
// heading changes of 90 and 180 degrees, scale changes 0.8-1.25 and 40 %
// overlap. Every published track is checked against the known mapping; the
// geometric check alone is checked on correspondences with planted outliers.
#include "processes/tracker/descriptor_matcher.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "synthetic_scene.h"

namespace nadir {
namespace {

using testing::SyntheticScene;

const cv::Size kFrame(612, 512);

CameraModel test_camera() {
  CameraModel c;
  c.width = kFrame.width;
  c.height = kFrame.height;
  c.fx = c.fy = 500.0;
  c.cx = 305.5;
  c.cy = 255.5;
  c.distortion = {0, 0, 0, 0, 0};
  return c;
}

const SyntheticScene& scene() {
  static const SyntheticScene s(cv::Size(1800, 1800), 23);
  return s;
}

// A frame looking at texture point `centre`, turned by `angle_deg`, with
// `scale` frame pixels per texture pixel and an optional perspective term.
struct View {
  cv::Point2d centre;
  double angle_deg = 0.0;
  double scale = 1.0;
  double tilt = 0.0;  // h31 of the homography, per texture pixel

  // Texture -> frame.
  cv::Matx33d homography() const {
    const double a = angle_deg * CV_PI / 180.0, c = std::cos(a) * scale, s = std::sin(a) * scale;
    const cv::Matx33d to_origin(1, 0, -centre.x, 0, 1, -centre.y, 0, 0, 1);
    const cv::Matx33d rotate(c, -s, 0, s, c, 0, tilt, 0, 1);
    const cv::Matx33d to_frame(1, 0, (kFrame.width - 1) / 2.0, 0, 1, (kFrame.height - 1) / 2.0, 0, 0, 1);
    return to_frame * rotate * to_origin;
  }
  cv::Mat render() const {
    cv::Mat out;
    cv::warpPerspective(scene().texture(), out, cv::Mat(homography()), kFrame, cv::INTER_LINEAR, cv::BORDER_REFLECT);
    return out;
  }
};

cv::Point2d apply(const cv::Matx33d& h, const cv::Point2d& p) {
  const cv::Vec3d q = h * cv::Vec3d(p.x, p.y, 1.0);
  return {q[0] / q[2], q[1] / q[2]};
}

DescriptorOptions options_for(const std::string& type) {
  DescriptorOptions o;
  o.type = type;
  return o;
}

struct PairResult {
  int tracks = 0;
  int candidates = 0;
  double median_error_px = 0;
  double p95_error_px = 0;
  double max_error_px = 0;
};

// Matches `from` -> `to` and measures every track against the true mapping.
PairResult match_pair(const std::string& type, const View& from, const View& to) {
  DescriptorMatcher matcher(options_for(type), test_camera());
  EXPECT_TRUE(matcher.process(from.render()).first_frame);
  const TrackStepResult step = matcher.process(to.render());
  const cv::Matx33d truth = to.homography() * from.homography().inv();
  PairResult r;
  r.tracks = static_cast<int>(step.tracks.size());
  r.candidates = matcher.last_stats().candidates;
  std::vector<double> errors;
  for (const FeatureTrack& t : step.tracks) {
    const cv::Point2d expected = apply(truth, cv::Point2d(t.prev_px));
    errors.push_back(std::hypot(expected.x - t.curr_px.x, expected.y - t.curr_px.y));
  }
  if (!errors.empty()) {
    std::sort(errors.begin(), errors.end());
    r.median_error_px = errors[errors.size() / 2];
    r.p95_error_px = errors[errors.size() * 95 / 100];
    r.max_error_px = errors.back();
  }
  std::cout << type << ": " << r.tracks << " tracks of " << r.candidates << " candidates, error median "
            << r.median_error_px << " px, 95 % " << r.p95_error_px << " px, max " << r.max_error_px << " px\n";
  return r;
}

class DescriptorPairs : public ::testing::TestWithParam<std::string> {};

// Minimum tracks per case: enough for the solver (it needs 8) with margin.
// Every track must follow the true mapping to within the RANSAC threshold
// (8 px, loose on purpose: relief and lens error); a wrong match is off by
// far more. Keypoint positions: AKAZE and SIFT are sub-pixel, ORB's come from
// its pyramid levels (up to 1.2^3 px steps).
void expect_good(const std::string& type, const PairResult& r, int min_tracks) {
  EXPECT_GE(r.tracks, min_tracks);
  EXPECT_GE(r.tracks, r.candidates * 3 / 4) << "inlier share of the candidates";
  EXPECT_LT(r.median_error_px, type == "orb" ? 2.0 : 1.0);
  EXPECT_LT(r.p95_error_px, type == "orb" ? 4.0 : 3.0);
  EXPECT_LT(r.max_error_px, 9.0) << "an outlier was published";
}

TEST_P(DescriptorPairs, HeadingReversalFullOverlap) {
  expect_good(GetParam(), match_pair(GetParam(), {{900, 900}, 0.0}, {{905, 897}, 180.0}), 150);
}

TEST_P(DescriptorPairs, QuarterTurn) {
  expect_good(GetParam(), match_pair(GetParam(), {{900, 900}, 10.0}, {{960, 880}, 100.0}), 150);
}

TEST_P(DescriptorPairs, ScaleChanges) {
  expect_good(GetParam(), match_pair(GetParam(), {{900, 900}, 0.0}, {{910, 905}, 20.0, 0.8}), 100);
  expect_good(GetParam(), match_pair(GetParam(), {{900, 900}, 0.0}, {{890, 910}, -30.0, 1.25}), 100);
}

TEST_P(DescriptorPairs, FortyPercentOverlapAcrossAReversalWithPerspective) {
  // 0.6 of the frame width along the line, heading reversed: 40 % overlap.
  expect_good(GetParam(), match_pair(GetParam(), {{800, 900}, 0.0}, {{800 + 0.6 * kFrame.width, 900}, 180.0, 1.0, 1e-4}), 40);
}

INSTANTIATE_TEST_SUITE_P(Types, DescriptorPairs, ::testing::Values("orb", "akaze", "sift"));

TEST(DescriptorMatcher, GeometricCheckRejectsPlantedOutliers) {
  for (const std::string geometry : {"homography", "fundamental"}) {
    DescriptorOptions o;
    o.geometry = geometry;
    const DescriptorMatcher matcher(o, test_camera());
    // A ground plane seen from two poses (a homography between the views),
    // 30 % of the correspondences replaced by random points.
    const View from{{900, 900}, 0.0}, to{{1000, 950}, 150.0, 1.1};
    const cv::Matx33d truth = to.homography() * from.homography().inv();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> x(0, kFrame.width - 1), y(0, kFrame.height - 1);
    const CameraModel camera = test_camera();
    std::vector<cv::Point2f> prev_px, curr_px;
    std::vector<bool> outlier;
    std::vector<DescriptorMatch> matches;
    for (int i = 0; i < 300; ++i) {
      const cv::Point2d p(x(rng), y(rng));
      const bool bad = i % 10 < 3;
      const cv::Point2d q = bad ? cv::Point2d(x(rng), y(rng)) : apply(truth, p);
      prev_px.emplace_back(p);
      curr_px.emplace_back(q);
      outlier.push_back(bad);
      matches.push_back({i, i});
    }
    const std::vector<DescriptorMatch> kept =
        matcher.geometric_inliers(camera.undistort(prev_px), camera.undistort(curr_px), matches);
    int good = 0, bad = 0;
    for (const DescriptorMatch& m : kept) {
      if (!outlier[static_cast<size_t>(m.prev)]) {
        ++good;
        continue;
      }
      // A random point can land near its true place by chance; that is no outlier.
      const cv::Point2d expected = apply(truth, cv::Point2d(prev_px[static_cast<size_t>(m.prev)]));
      const cv::Point2f got = curr_px[static_cast<size_t>(m.curr)];
      if (std::hypot(expected.x - got.x, expected.y - got.y) > 8.0) ++bad;
    }
    // Point-to-point (homography): every planted outlier goes; point-to-line
    // (fundamental): one lying near its epipolar line may stay.
    EXPECT_EQ(good, 210) << geometry;
    EXPECT_LE(bad, geometry == "homography" ? 0 : 9) << geometry;
    std::cout << geometry << ": " << good << " of 210 true matches kept, " << bad << " of 90 outliers\n";
  }
}

TEST(DescriptorMatcher, TooFewCandidatesGiveNoTracks) {
  DescriptorOptions o;
  o.min_matches = 20;
  const DescriptorMatcher matcher(o, test_camera());
  std::vector<cv::Point2d> a, b;
  std::vector<DescriptorMatch> matches;
  for (int i = 0; i < 19; ++i) {
    a.emplace_back(0.01 * i, 0.02 * (i % 5));
    b.emplace_back(0.01 * i + 0.1, 0.02 * (i % 5));
    matches.push_back({i, i});
  }
  EXPECT_TRUE(matcher.geometric_inliers(a, b, matches).empty());
  a.emplace_back(0.3, 0.3);
  b.emplace_back(0.4, 0.3);
  matches.push_back({19, 19});
  EXPECT_EQ(matcher.geometric_inliers(a, b, matches).size(), 20u);
}

TEST(DescriptorMatcher, KeypointsCoverTheImage) {
  const DescriptorMatcher matcher(options_for("orb"), test_camera());
  const DescribedFrame frame = matcher.describe(View{{900, 900}, 0.0}.render());
  EXPECT_LE(frame.px.size(), 1500u);
  EXPECT_GT(frame.px.size(), 1000u);
  // Every cell of the default 6x5 grid holds keypoints.
  std::vector<int> per_cell(30, 0);
  for (const cv::Point2f& p : frame.px) {
    EXPECT_GE(p.x, 16.0f);
    EXPECT_GE(p.y, 16.0f);
    EXPECT_LE(p.x, kFrame.width - 17.0f);
    EXPECT_LE(p.y, kFrame.height - 17.0f);
    ++per_cell[static_cast<size_t>(static_cast<int>(p.y * 5 / kFrame.height) * 6 + static_cast<int>(p.x * 6 / kFrame.width))];
  }
  for (int n : per_cell) EXPECT_GE(n, 15);
  ASSERT_EQ(frame.norm.size(), frame.px.size());
  EXPECT_NEAR(frame.norm[0].x, (frame.px[0].x - 305.5) / 500.0, 1e-9);
}

TEST(DescriptorMatcher, IdsPersistAndAgesCountAcrossPairs) {
  DescriptorMatcher matcher(options_for("orb"), test_camera());
  const std::vector<View> views = {{{900, 900}, 0.0}, {{960, 900}, 60.0}, {{1020, 910}, 180.0}};
  std::vector<TrackStepResult> steps;
  for (const View& v : views) steps.push_back(matcher.process(v.render()));
  ASSERT_GT(steps[1].tracks.size(), 100u);
  ASSERT_GT(steps[2].tracks.size(), 100u);
  std::map<int64_t, cv::Point2f> earlier;
  for (const FeatureTrack& t : steps[1].tracks) {
    EXPECT_EQ(t.age, 2);
    earlier[t.id] = t.curr_px;
  }
  int chained = 0;
  int64_t last_id = 0;
  for (const FeatureTrack& t : steps[2].tracks) {
    EXPECT_GT(t.id, last_id) << "ids ascend";
    last_id = t.id;
    const auto it = earlier.find(t.id);
    if (it == earlier.end()) {
      EXPECT_EQ(t.age, 2);
      continue;
    }
    ++chained;
    EXPECT_EQ(t.age, 3);
    EXPECT_EQ(it->second.x, t.prev_px.x);
    EXPECT_EQ(it->second.y, t.prev_px.y);
  }
  EXPECT_GT(chained, 50);
}

TEST(DescriptorMatcher, SameFramesGiveSameTracksOnAnyThreadCount) {
  for (const std::string type : {"orb", "akaze", "sift"}) {
    std::vector<std::vector<FeatureTrack>> runs;
    // Once on one thread, once on OpenCV's default pool.
    const int threads = cv::getNumThreads();
    for (int run = 0; run < 2; ++run) {
      cv::setNumThreads(run == 0 ? 1 : threads);
      DescriptorMatcher matcher(options_for(type), test_camera());
      matcher.process(View{{900, 900}, 0.0}.render());
      runs.push_back(matcher.process(View{{980, 930}, 170.0, 0.9}.render()).tracks);
    }
    cv::setNumThreads(threads);
    ASSERT_EQ(runs[0].size(), runs[1].size()) << type;
    ASSERT_FALSE(runs[0].empty()) << type;
    for (size_t i = 0; i < runs[0].size(); ++i) {
      EXPECT_EQ(runs[0][i].id, runs[1][i].id);
      EXPECT_EQ(runs[0][i].prev_px, runs[1][i].prev_px);
      EXPECT_EQ(runs[0][i].curr_px, runs[1][i].curr_px);
    }
  }
}

TEST(DescriptorMatcher, ImageSizeChangeStartsAfresh) {
  DescriptorMatcher matcher(options_for("orb"), test_camera());
  matcher.process(View{{900, 900}, 0.0}.render());
  cv::Mat smaller;
  cv::resize(View{{900, 900}, 0.0}.render(), smaller, cv::Size(400, 300));
  EXPECT_TRUE(matcher.process(smaller).first_frame);
  EXPECT_THROW(matcher.process(cv::Mat()), std::invalid_argument);
}

}  // namespace
}  // namespace nadir
