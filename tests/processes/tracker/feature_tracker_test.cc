// FeatureTracker on generated imagery: known motion is recovered to
// sub-pixel, occluded patches are rejected, ids and ages persist.
#include "processes/tracker/feature_tracker.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "synthetic_scene.h"

namespace nadir {
namespace {

using testing::SyntheticScene;
using testing::ViewPose;

const cv::Size kFrame(612, 512);
constexpr double kPi = 3.14159265358979323846;

const SyntheticScene& scene() {
  static const SyntheticScene s(cv::Size(1600, 1600), 42);
  return s;
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * (v.size() - 1))];
}

// Tracking errors against where the geometry says each point must be.
std::vector<double> track_errors(const TrackStepResult& step, const ViewPose& a, const ViewPose& b) {
  std::vector<double> errors;
  for (const FeatureTrack& t : step.tracks) {
    const cv::Point2d expected = SyntheticScene::map_point(t.prev_px, a, b, kFrame);
    errors.push_back(std::hypot(t.curr_px.x - expected.x, t.curr_px.y - expected.y));
  }
  return errors;
}

TEST(FeatureTracker, FirstFrameDetects450SpacedCornersOnAGrid) {
  FeatureTracker tracker{TrackerOptions{}};
  const TrackStepResult step = tracker.process(scene().render({{800, 800}, 0.0}, kFrame));
  EXPECT_TRUE(step.first_frame);
  EXPECT_TRUE(step.tracks.empty());
  EXPECT_EQ(step.features_after, 450);
  EXPECT_EQ(step.cells_replenished, 9);

  const TrackerOptions o;
  GridCornerDetector grid(o);
  std::map<int, int> per_cell;
  const auto& f = tracker.features();
  for (size_t i = 0; i < f.size(); ++i) {
    ++per_cell[grid.cell_index(kFrame, f[i].px)];
    EXPECT_GE(f[i].px.x, o.border_px);
    EXPECT_LE(f[i].px.x, kFrame.width - 1 - o.border_px);
    for (size_t j = i + 1; j < f.size(); ++j) {
      EXPECT_GE(std::hypot(f[i].px.x - f[j].px.x, f[i].px.y - f[j].px.y), o.min_distance_px);
    }
  }
  ASSERT_EQ(per_cell.size(), 9u);
  for (const auto& [cell, count] : per_cell) EXPECT_EQ(count, 50) << "cell " << cell;
}

TEST(FeatureTracker, RecoversAKnownShiftToSubPixel) {
  FeatureTracker tracker{TrackerOptions{}};
  const ViewPose a{{800, 800}, 0.0};
  const ViewPose b{{807.3, 795.4}, 0.0};  // scene moves by (-7.3, +4.6) px in the image
  tracker.process(scene().render(a, kFrame));
  const TrackStepResult step = tracker.process(scene().render(b, kFrame));
  ASSERT_GT(step.tracks.size(), 400u);

  cv::Point2d mean_flow(0, 0);
  for (const FeatureTrack& t : step.tracks) mean_flow += cv::Point2d(t.curr_px - t.prev_px);
  mean_flow /= static_cast<double>(step.tracks.size());
  EXPECT_NEAR(mean_flow.x, -7.3, 0.02);
  EXPECT_NEAR(mean_flow.y, 4.6, 0.02);

  const std::vector<double> errors = track_errors(step, a, b);
  EXPECT_LT(percentile(errors, 0.5), 0.05);
  EXPECT_LT(percentile(errors, 0.95), 0.15);
  EXPECT_LT(*std::max_element(errors.begin(), errors.end()), 0.5);
}

// Rotation angle of the tracks (2-D Procrustes about the centroids).
double track_rotation(const TrackStepResult& step) {
  cv::Point2d cp(0, 0), cc(0, 0);
  for (const FeatureTrack& t : step.tracks) {
    cp += cv::Point2d(t.prev_px);
    cc += cv::Point2d(t.curr_px);
  }
  cp /= static_cast<double>(step.tracks.size());
  cc /= static_cast<double>(step.tracks.size());
  double s_cos = 0, s_sin = 0;
  for (const FeatureTrack& t : step.tracks) {
    const cv::Point2d p = cv::Point2d(t.prev_px) - cp, c = cv::Point2d(t.curr_px) - cc;
    s_cos += p.x * c.x + p.y * c.y;
    s_sin += p.x * c.y - p.y * c.x;
  }
  return std::atan2(s_sin, s_cos);
}

// KLT fits a translation to each 21x21 window, so under rotation it follows
// the window's gradient-weighted centre rather than the corner itself: the
// error grows with the rotation between frames, about 0.035 px per degree
// on this texture. A realistic 0.3 deg/frame turn stays within hundredths
// of a pixel; 2 deg (28 deg/s at 14 Hz) within a quarter pixel.
TEST(FeatureTracker, RecoversAKnownRotationToSubPixel) {
  struct Case {
    double degrees, median_px, p95_px, max_px;
  };
  for (const Case& c : {Case{0.3, 0.02, 0.04, 0.08}, Case{2.0, 0.1, 0.2, 0.35}}) {
    SCOPED_TRACE(c.degrees);
    FeatureTracker tracker{TrackerOptions{}};
    const ViewPose a{{800, 800}, 0.0};
    const double angle = c.degrees * kPi / 180.0;
    const ViewPose b{{803.0, 798.0}, angle};
    tracker.process(scene().render(a, kFrame));
    const TrackStepResult step = tracker.process(scene().render(b, kFrame));
    ASSERT_GT(step.tracks.size(), 400u);

    const std::vector<double> errors = track_errors(step, a, b);
    EXPECT_LT(percentile(errors, 0.5), c.median_px);
    EXPECT_LT(percentile(errors, 0.95), c.p95_px);
    EXPECT_LT(*std::max_element(errors.begin(), errors.end()), c.max_px);
    // The image turns by -angle when the camera turns by +angle.
    EXPECT_NEAR(track_rotation(step), -angle, 0.01 * angle);
  }
}

// With the window warp, the turned windows of a turning view are matched
// as such: the error falls well below the plain KLT's on the same pair.
TEST(FeatureTracker, WindowWarpFollowsATurningView) {
  const ViewPose a{{800, 800}, 0.0}, b{{803.0, 798.0}, 2.0 * kPi / 180.0};
  double medians[2] = {0, 0};
  for (const bool warp : {false, true}) {
    TrackerOptions options;
    options.klt_window_warp = warp;
    FeatureTracker tracker{options};
    tracker.process(scene().render(a, kFrame));
    const TrackStepResult step = tracker.process(scene().render(b, kFrame));
    ASSERT_GT(step.tracks.size(), 400u);
    medians[warp] = percentile(track_errors(step, a, b), 0.5);
  }
  EXPECT_GT(medians[0], 0.03);
  EXPECT_LT(medians[1], medians[0] / 3) << "plain " << medians[0] << " px";
}

// The scene seen through a barrel-distorting lens: a wide pinhole view of
// the texture, resampled at every pixel's undistorted ray.
class LensView {
 public:
  explicit LensView(const CameraModel& lens) : lens_(lens) {
    std::vector<cv::Point2f> pixels;
    for (int v = 0; v < kFrame.height; ++v)
      for (int u = 0; u < kFrame.width; ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
    const std::vector<cv::Point2d> rays = lens_.undistort(pixels);
    map_x_.create(kFrame, CV_32F);
    map_y_.create(kFrame, CV_32F);
    for (size_t i = 0; i < rays.size(); ++i) {
      const cv::Point2d w = wide_pixel(rays[i]);
      map_x_.at<float>(static_cast<int>(i)) = static_cast<float>(w.x);
      map_y_.at<float>(static_cast<int>(i)) = static_cast<float>(w.y);
    }
  }
  cv::Mat render(const ViewPose& pose) const {
    cv::Mat out;
    cv::remap(scene().render(pose, kWide), out, map_x_, map_y_, cv::INTER_CUBIC, cv::BORDER_REFLECT_101);
    return out;
  }
  // Where pixel `p` of the view at `from` appears in the view at `to`.
  cv::Point2d map_point(const cv::Point2f& p, const ViewPose& from, const ViewPose& to) const {
    const cv::Point2d w = SyntheticScene::map_point(wide_pixel(lens_.undistort({p})[0]), from, to, kWide);
    const cv::Point2d ray((w.x - kWideCentre.x) / lens_.fx, (w.y - kWideCentre.y) / lens_.fy);
    const cv::Point2f px = lens_.distort({ray})[0];
    return {px.x, px.y};
  }

 private:
  cv::Point2d wide_pixel(const cv::Point2d& ray) const {
    return {kWideCentre.x + lens_.fx * ray.x, kWideCentre.y + lens_.fy * ray.y};
  }
  const cv::Size kWide{1200, 1100};
  const cv::Point2d kWideCentre{599.5, 549.5};
  CameraModel lens_;
  cv::Mat map_x_, map_y_;
};

// Through a strongly distorting lens a window is magnified differently at a
// track's two ends, which a translation-only KLT partly reads as a shift.
// The warp with the lens's own magnification at both ends removes that part.
TEST(FeatureTracker, WindowWarpFollowsTheLensMagnification) {
  CameraModel lens = CameraModel::pinhole(kFrame.width, kFrame.height, 400.0);
  lens.distortion = {-0.3, 0.08, 0.0, 0.0, 0.0};
  const LensView view(lens);
  const std::vector<ViewPose> poses = {{{800, 800}, 0.0}, {{788, 806}, 0.0}, {{776, 812}, 0.0}, {{764, 818}, 0.0}};
  double medians[2] = {0, 0};
  for (const bool warp : {false, true}) {
    TrackerOptions options;
    options.klt_window_warp = warp;
    FeatureTracker tracker{options, &lens};
    tracker.process(view.render(poses[0]));
    std::vector<double> errors;
    for (size_t k = 1; k < poses.size(); ++k) {
      const TrackStepResult step = tracker.process(view.render(poses[k]));
      for (const FeatureTrack& t : step.tracks) {
        const cv::Point2d truth = view.map_point(t.prev_px, poses[k - 1], poses[k]);
        errors.push_back(std::hypot(t.curr_px.x - truth.x, t.curr_px.y - truth.y));
      }
    }
    ASSERT_GT(errors.size(), 1000u);
    medians[warp] = percentile(errors, 0.5);
  }
  RecordProperty("median_plain_mpx", static_cast<int>(medians[0] * 1e3));
  RecordProperty("median_warped_mpx", static_cast<int>(medians[1] * 1e3));
  EXPECT_LT(medians[1], 0.7 * medians[0]) << "plain " << medians[0] << " px, warped " << medians[1] << " px";
}

// A deformation the tracker knows nothing about (the lens is not given to
// it: as unmodelled relief would) is learnt from the neighbours' tracks: with
// klt_local_warp each feature's window follows the last pair's linear map
// around it, and from the second pair on the error falls below the global
// warp's.
TEST(FeatureTracker, LocalWarpLearnsADeformationFromTheNeighbours) {
  CameraModel lens = CameraModel::pinhole(kFrame.width, kFrame.height, 400.0);
  lens.distortion = {-0.3, 0.08, 0.0, 0.0, 0.0};
  const LensView view(lens);
  std::vector<ViewPose> poses;
  for (int k = 0; k < 6; ++k) poses.push_back({{800.0 - 12.0 * k, 800.0 + 6.0 * k}, 0.0});
  double medians[2] = {0, 0};
  for (const bool local : {false, true}) {
    TrackerOptions options;
    options.klt_window_warp = true;
    options.klt_local_warp = local;
    FeatureTracker tracker{options};  // no lens: the image motion is all it knows
    tracker.process(view.render(poses[0]));
    std::vector<double> errors;
    int with_local = 0;
    for (size_t k = 1; k < poses.size(); ++k) {
      for (const auto& f : tracker.features()) with_local += f.has_local_warp;
      const TrackStepResult step = tracker.process(view.render(poses[k]));
      if (k < 2) continue;  // the first pair has no local maps yet
      for (const FeatureTrack& t : step.tracks) {
        const cv::Point2d truth = view.map_point(t.prev_px, poses[k - 1], poses[k]);
        errors.push_back(std::hypot(t.curr_px.x - truth.x, t.curr_px.y - truth.y));
      }
    }
    ASSERT_GT(errors.size(), 1000u);
    if (local) EXPECT_GT(with_local, 1500);
    else EXPECT_EQ(with_local, 0);
    medians[local] = percentile(errors, 0.5);
  }
  RecordProperty("median_global_mpx", static_cast<int>(medians[0] * 1e3));
  RecordProperty("median_local_mpx", static_cast<int>(medians[1] * 1e3));
  EXPECT_LT(medians[1], 0.8 * medians[0]) << "global " << medians[0] << " px, local " << medians[1] << " px";
}

// Replaces a square of `frame` by unrelated texture (an occluder).
cv::Mat occlude(const cv::Mat& frame, const cv::Rect& box) {
  cv::Mat out = frame.clone();
  const SyntheticScene other(cv::Size(box.width, box.height), 777);
  other.texture().copyTo(out(box));
  return out;
}

TEST(FeatureTracker, ForwardBackwardCheckRejectsAnOccludedPatch) {
  const ViewPose a{{800, 800}, 0.0};
  const ViewPose b{{803.0, 802.0}, 0.0};  // the scene moves by (-3, -2) px
  const cv::Mat first = scene().render(a, kFrame);
  const cv::Rect box(230, 190, 150, 130);
  const cv::Mat second = occlude(scene().render(b, kFrame), box);
  // Features whose whole KLT window is occluded in the second frame have no
  // true match there.
  const cv::Rect deep(box.x + 11, box.y + 11, box.width - 22, box.height - 22);
  auto hidden = [&](const cv::Point2f& p) { return deep.contains(cv::Point(cvRound(p.x - 3), cvRound(p.y - 2))); };

  auto run = [&](double fb_threshold, bool patch_check) {
    TrackerOptions o;
    o.fb_threshold_px = fb_threshold;
    if (!patch_check) o.patch_error_floor = 255.0;  // no patch can differ by more
    FeatureTracker tracker(o);
    tracker.process(first);
    int features_hidden = 0;
    for (const auto& f : tracker.features()) features_hidden += hidden(f.px);
    EXPECT_GT(features_hidden, 15);
    return tracker.process(second);
  };
  auto hidden_survivors = [&](const TrackStepResult& step) {
    int n = 0;
    for (const FeatureTrack& t : step.tracks) n += hidden(t.prev_px);
    return n;
  };

  // Without checks KLT "tracks" the hidden features onto the occluder.
  const TrackStepResult unchecked = run(1e6, false);
  const int unchecked_hidden = hidden_survivors(unchecked);
  EXPECT_GT(unchecked_hidden, 15);
  EXPECT_EQ(unchecked.fb_rejected, 0);
  // The forward-backward check alone rejects nearly all of them: a few
  // wrong matches in the occluder are consistent both ways.
  const TrackStepResult fb_only = run(1.0, false);
  EXPECT_GE(fb_only.fb_rejected, unchecked_hidden - 5);
  EXPECT_LE(hidden_survivors(fb_only), 5);
  // With the photometric check as well (the default) none survives, and
  // what remains is exact.
  const TrackStepResult checked = run(1.0, true);
  EXPECT_EQ(hidden_survivors(checked), 0);
  EXPECT_GT(checked.fb_rejected, 15);
  const std::vector<double> errors = track_errors(checked, a, b);
  EXPECT_LT(*std::max_element(errors.begin(), errors.end()), 0.5);
}

// Scouted tracking (the default) against the plain pyramid for every
// feature, over a view that speeds up, turns, and carries a patch moving 25 px
// against the scene (a vehicle): 25 px is far beyond a single level's reach,
// so the patch's features only come out right through the full-pyramid retry.
TEST(FeatureTracker, ScoutedTrackingMatchesThePlainPyramid) {
  // Without the window warp: the scouts warp by the previous pair's motion,
  // the plain pyramid by this one's, which this view changes on purpose (the
  // warp has its own tests above).
  TrackerOptions scouted_options;
  scouted_options.klt_window_warp = false;
  TrackerOptions plain_options = scouted_options;
  plain_options.klt_predicted_levels = plain_options.klt_pyramid_levels;
  FeatureTracker scouted(scouted_options);
  FeatureTracker plain(plain_options);
  const std::vector<ViewPose> poses = {
      {{800, 800}, 0.0}, {{802, 801}, 0.0}, {{804, 802}, 0.0}, {{814, 806}, 0.01}, {{826, 809}, 0.04}};
  const cv::Rect vehicle(300, 200, 160, 160);
  const cv::Point2d vehicle_shift(25.0, 0.0);  // texture offset inside the patch in the last frame
  const cv::Rect inner(vehicle.x + 15, vehicle.y + 15, vehicle.width - 30, vehicle.height - 30);
  for (size_t k = 0; k < poses.size(); ++k) {
    cv::Mat frame = scene().render(poses[k], kFrame);
    const bool last = k + 1 == poses.size();
    ViewPose moved = poses[k];
    moved.centre -= vehicle_shift;
    if (last) scene().render(moved, kFrame)(vehicle).copyTo(frame(vehicle));
    const TrackStepResult a = scouted.process(frame);
    const TrackStepResult b = plain.process(frame);
    if (k == 0) continue;
    SCOPED_TRACE(k);
    // Same survivors, same positions to well under the KLT's own precision.
    std::map<int64_t, cv::Point2f> plain_tracks;
    for (const FeatureTrack& t : b.tracks) plain_tracks[t.id] = t.curr_px;
    int common = 0;
    std::vector<double> differences;
    for (const FeatureTrack& t : a.tracks) {
      const auto it = plain_tracks.find(t.id);
      if (it == plain_tracks.end()) continue;
      ++common;
      differences.push_back(std::hypot(t.curr_px.x - it->second.x, t.curr_px.y - it->second.y));
    }
    EXPECT_GE(common, static_cast<int>(b.tracks.size()) - 2);
    EXPECT_LE(a.tracks.size(), b.tracks.size() + 2);
    EXPECT_LT(percentile(differences, 0.5), 0.005);
    EXPECT_LT(*std::max_element(differences.begin(), differences.end()), 0.05);
    if (!last) {
      const std::vector<double> errors = track_errors(a, poses[k - 1], poses[k]);
      EXPECT_LT(percentile(errors, 0.95), 0.15);
      continue;
    }
    // The vehicle's inner features: tracked to where the patch took them.
    auto on_vehicle = [&](const TrackStepResult& step) {
      int n = 0;
      for (const FeatureTrack& t : step.tracks) {
        if (!inner.contains(cv::Point(cvRound(t.prev_px.x), cvRound(t.prev_px.y)))) continue;
        const cv::Point2d expected = SyntheticScene::map_point(t.prev_px, poses[k - 1], moved, kFrame);
        if (!inner.contains(cv::Point(cvRound(expected.x), cvRound(expected.y)))) continue;
        n += std::hypot(t.curr_px.x - expected.x, t.curr_px.y - expected.y) < 0.2;
      }
      return n;
    };
    // (One may fall either side of the photometric check, whose limit comes
    // from the frame's median patch error over tracks that differ slightly.)
    EXPECT_GT(on_vehicle(b), 8);
    EXPECT_GE(on_vehicle(a), on_vehicle(b) - 1);
  }
}

TEST(FeatureTracker, IdsAndAgesPersistAcrossFramesAndReplenishment) {
  FeatureTracker tracker{TrackerOptions{}};
  std::map<int64_t, int32_t> last_age;
  std::set<int64_t> ever_seen;
  int64_t max_id_before = 0;
  for (int k = 0; k < 25; ++k) {
    // Steady drift and a slow turn: features leave at one edge, cells refill.
    const ViewPose pose{{800 + 6.0 * k, 800 + 2.0 * k}, 0.004 * k};
    const TrackStepResult step = tracker.process(scene().render(pose, kFrame, 1.0, 100 + k));
    if (k == 0) {
      for (const auto& f : tracker.features()) max_id_before = std::max(max_id_before, f.id);
      continue;
    }
    int64_t prev_id = 0;
    for (const FeatureTrack& t : step.tracks) {
      EXPECT_GT(t.id, prev_id) << "tracks are in ascending id order";
      prev_id = t.id;
      const auto it = last_age.find(t.id);
      if (it != last_age.end()) {
        EXPECT_EQ(t.age, it->second + 1) << "id " << t.id;
      } else {
        EXPECT_FALSE(ever_seen.count(t.id)) << "a lost id came back: " << t.id;
      }
      EXPECT_GE(t.age, 2);
    }
    std::map<int64_t, int32_t> ages;
    for (const FeatureTrack& t : step.tracks) ages[t.id] = t.age;
    for (const auto& [id, age] : ages) ever_seen.insert(id);
    last_age = ages;
    EXPECT_GT(step.tracks.size(), 300u);
  }
  // Some first-frame features lived through all 25 frames...
  int oldest = 0;
  for (const auto& [id, age] : last_age) oldest = std::max(oldest, age);
  EXPECT_EQ(oldest, 25);
  // ...and new ids were handed out as the view moved on.
  EXPECT_GT(last_age.rbegin()->first, max_id_before);
}

TEST(FeatureTracker, SameImagesGiveIdenticalTracks) {
  auto run = [] {
    FeatureTracker tracker{TrackerOptions{}};
    std::vector<FeatureTrack> all;
    for (int k = 0; k < 6; ++k) {
      const TrackStepResult step = tracker.process(scene().render({{700 + 4.0 * k, 900 - 3.0 * k}, 0.01 * k}, kFrame, 2.0, k));
      all.insert(all.end(), step.tracks.begin(), step.tracks.end());
    }
    return all;
  };
  const std::vector<FeatureTrack> a = run(), b = run();
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 1000u);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id);
    EXPECT_EQ(a[i].age, b[i].age);
    EXPECT_EQ(a[i].prev_px, b[i].prev_px);
    EXPECT_EQ(a[i].curr_px, b[i].curr_px);
  }
}

TEST(FeatureTracker, SensorNoiseAloneYieldsNoCorners) {
  // Flat grey with 1 grey level of noise: the relative quality level alone
  // would pick 450 noise "corners"; the absolute Harris floor picks none.
  cv::Mat flat(kFrame, CV_8UC1, cv::Scalar(120));
  cv::Mat noise(kFrame, CV_8SC1);
  cv::RNG(9).fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  cv::add(flat, noise, flat, cv::noArray(), CV_8U);
  FeatureTracker tracker{TrackerOptions{}};
  EXPECT_EQ(tracker.process(flat).features_after, 0);

  TrackerOptions no_floor;
  no_floor.min_harris_response = 0.0;
  FeatureTracker fooled(no_floor);
  EXPECT_GT(fooled.process(flat).features_after, 400);
}

TEST(FeatureTracker, RejectsImagesThatAreNot8BitMono) {
  FeatureTracker tracker{TrackerOptions{}};
  EXPECT_THROW(tracker.process(cv::Mat(kFrame, CV_16UC1, cv::Scalar(0))), std::invalid_argument);
  EXPECT_THROW(tracker.process(cv::Mat()), std::invalid_argument);
}

}  // namespace
}  // namespace nadir
