// nadir_track_truth against a short simulated flight over relief (ideal
// sensors): tracks built from the simulated world with known errors added
// must come back with exactly those errors; rewritten tracks with none.
#include "tools/track_truth/track_truth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "common/camera_model.h"
#include "common/channels.h"
#include "common/config.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/tracks_t.hpp"
#include "processes/sim/flight_profile.h"
#include "processes/sim/sensor_options.h"
#include "processes/sim/sim_camera.h"
#include "processes/sim/simulator.h"
#include "tests/common/test_support.h"

namespace nadir::track_truth {
namespace {

std::string source_path(const std::string& relative) { return std::string(NADIR_SOURCE_DIR) + "/" + relative; }

// One second of rough_120 (relief x3) with ideal sensors: the simulator's
// CONFIG, its frame truth and the images' sensor times.
struct Flight {
  std::string sim_config;
  std::vector<ground_truth_t> truth;
  std::vector<int64_t> frame_utimes;
  std::map<int64_t, double> altimeter_range_m;  // by sensor time
};

const Flight& flight() {
  static const Flight f = [] {
    Flight out;
    const Config root = Config::load_file(source_path("config/default.yaml"));
    sim::SimulatorOptions options;
    options.seed = 3;
    options.duration_s = 1.0;
    options.camera_yaml = root.section("camera").dump();
    sim::Simulator simulator(
        sim::FlightProfile::load(source_path("config/profiles/rough_120.yaml")), sim::SimCamera::from_config(root),
        sim::SensorOptions::from_config(Config::load_file(source_path("config/sim_sensors.yaml")), "ideal"), options);
    sim::SimEvent e;
    while (simulator.next(&e)) {
      std::string why;
      if (e.channel == channels::kConfig) {
        config_t c;
        if (decode_message(e.data.data(), e.data.size(), &c, &why)) out.sim_config = c.yaml;
      } else if (e.channel == channels::kGroundTruth) {
        ground_truth_t g;
        if (decode_message(e.data.data(), e.data.size(), &g, &why)) out.truth.push_back(g);
      } else if (e.channel == channels::kAltimeter) {
        altimeter_t a;
        if (decode_message(e.data.data(), e.data.size(), &a, &why)) out.altimeter_range_m[a.utime] = a.range_m;
      } else if (e.channel == channels::kCameraImage) {
        image_t i;
        if (decode_message(e.data.data(), e.data.size(), &i, &why)) out.frame_utimes.push_back(i.utime);
      }
    }
    return out;
  }();
  return f;
}

SimScene scene_of(const Flight& f) {
  SimScene scene(f.sim_config, "test CONFIG");
  for (const ground_truth_t& g : f.truth) scene.add_truth(g);
  return scene;
}

CameraModel estimator_camera() {
  return CameraModel::from_config(Config::load_file(source_path("config/default.yaml")));
}

// Tracks on a grid of the first frame, followed through every frame as a
// tracker with a known error would: each step lands on the exact image of the
// ground under the track's prev pixel plus `step_error` px in x plus
// `expansion` times the offset from the principal point. A track's error so
// accumulates with its age (its drift).
std::vector<tracks_t> tracks_along(const SimScene& scene, const Flight& f, double step_error, double expansion = 0.0) {
  const CameraModel camera = estimator_camera();
  const Eigen::Vector2d principal(scene.camera().cx, scene.camera().cy);
  std::vector<tracks_t> out;
  std::map<int64_t, Eigen::Vector2d> tracked;  // the "tracker's" position in the last frame
  int64_t id = 0;
  for (int v = 60; v < 480; v += 40)
    for (int u = 60; u < 560; u += 40) tracked[id++] = Eigen::Vector2d(u, v);
  for (size_t k = 1; k < f.frame_utimes.size(); ++k) {
    CameraPose prev, curr;
    if (!scene.pose_at(f.frame_utimes[k - 1], &prev) || !scene.pose_at(f.frame_utimes[k], &curr)) continue;
    tracks_t t;
    t.utime = f.frame_utimes[k];
    t.prev_utime = f.frame_utimes[k - 1];
    t.frame_counter = static_cast<int64_t>(k);
    t.width = 612;
    t.height = 512;
    t.flags = 0;
    t.num_tracks = 0;
    for (auto& [track, px] : tracked) {
      Eigen::Vector3d ground;
      Eigen::Vector2d exact;
      if (!scene.ground_point(prev, px, &ground) || !scene.pixel_of(curr, ground, &exact)) continue;
      const Eigen::Vector2d prev_px = px;
      const Eigen::Vector2d curr_px = exact + Eigen::Vector2d(step_error, 0.0) + expansion * (exact - principal);
      px = curr_px;
      const auto pn = camera.undistort({cv::Point2f(static_cast<float>(prev_px.x()), static_cast<float>(prev_px.y()))});
      const auto cn = camera.undistort({cv::Point2f(static_cast<float>(curr_px.x()), static_cast<float>(curr_px.y()))});
      t.track_id.push_back(track);
      t.age.push_back(static_cast<int32_t>(k));
      t.prev_px.push_back({static_cast<float>(prev_px.x()), static_cast<float>(prev_px.y())});
      t.curr_px.push_back({static_cast<float>(curr_px.x()), static_cast<float>(curr_px.y())});
      t.prev_norm.push_back({pn[0].x, pn[0].y});
      t.curr_norm.push_back({cn[0].x, cn[0].y});
      ++t.num_tracks;
    }
    out.push_back(t);
  }
  return out;
}

TEST(SimScene, RebuildsTheWorldTheSimulatorFlew) {
  const Flight& f = flight();
  ASSERT_FALSE(f.sim_config.empty());
  ASSERT_EQ(f.frame_utimes.size(), 15u);  // t = 0 to 1 s at 14 Hz
  const SimScene scene = scene_of(f);
  EXPECT_EQ(scene.seed(), 3u);
  EXPECT_DOUBLE_EQ(scene.relief_scale(), 3.0);
  EXPECT_EQ(scene.frames(), 15u);
  // The ideal altimeter looks down the optical axis from the camera's
  // centre: where a frame and a range share their time, the ray through the
  // principal point meets the ground at that range (the simulator's own
  // altimeter path, not this tool's).
  int compared = 0;
  for (const int64_t utime : f.frame_utimes) {
    const auto range = f.altimeter_range_m.find(utime);
    if (range == f.altimeter_range_m.end()) continue;
    CameraPose pose;
    ASSERT_TRUE(scene.pose_at(utime, &pose));
    Eigen::Vector3d point;
    const sim::SimCamera& c = scene.camera();
    ASSERT_TRUE(scene.ground_point(pose, Eigen::Vector2d(c.cx, c.cy), &point));
    EXPECT_NEAR((point - pose.centre).norm(), range->second, 1e-3) << utime;
    Eigen::Vector2d back;
    ASSERT_TRUE(scene.pixel_of(pose, point, &back));
    EXPECT_NEAR(back.x(), c.cx, 1e-6);
    EXPECT_NEAR(back.y(), c.cy, 1e-6);
    EXPECT_TRUE(scene.visible(pose, point));
    ++compared;
  }
  EXPECT_EQ(compared, 3);  // t = 0, 0.5 and 1 s
  CameraPose none;
  EXPECT_FALSE(scene.pose_at(f.frame_utimes.back() + 1000000, &none));
}

TEST(SimScene, ANonSimulatorConfigIsRefusedByName) {
  try {
    SimScene scene("name: tracker\n", "x.lcmlog: CONFIG");
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("name"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("x.lcmlog"), std::string::npos) << e.what();
  }
}

TEST(TrackTruth, ExactTracksHaveNoError) {
  const Flight& f = flight();
  const SimScene scene = scene_of(f);
  std::vector<tracks_t> tracks = tracks_along(scene, f, 0.0);
  ASSERT_EQ(tracks.size(), 14u);
  TrackTruth compare(scene, estimator_camera());
  for (tracks_t& t : tracks) compare.process(&t, Rewrite::kNone);
  const TrackTruthReport r = compare.report();
  EXPECT_EQ(r.messages, 14);
  EXPECT_EQ(r.messages_without_truth, 0);
  EXPECT_GT(r.tracks, 14 * 100);
  EXPECT_EQ(r.ray_misses, 0);
  EXPECT_GT(r.flow.count, 14 * 100);
  EXPECT_LT(r.flow.rms, 1e-3);  // float pixels
  ASSERT_FALSE(r.drift_by_age.empty());
  for (const AgeBin& bin : r.drift_by_age) EXPECT_LT(bin.drift.rms, 1e-3) << bin.from;
}

TEST(TrackTruth, MeasuresAKnownStepErrorAndTheDriftItAccumulates) {
  const Flight& f = flight();
  const SimScene scene = scene_of(f);
  const double step = 0.05;
  std::vector<tracks_t> tracks = tracks_along(scene, f, step);
  TrackTruth compare(scene, estimator_camera());
  for (tracks_t& t : tracks) compare.process(&t, Rewrite::kNone);
  const TrackTruthReport r = compare.report();
  // One step: the track's prev pixel is already off, but the exact image of
  // the ground under it moves with it; what is left is the step's own error.
  EXPECT_NEAR(r.flow.mean_x, step, 2e-3);
  EXPECT_NEAR(r.flow.mean_y, 0.0, 2e-3);
  EXPECT_NEAR(r.flow_expansion_per_frame, 0.0, 1e-6);
  // Drift: age a is a * step off (ages 1-4, 5-9 and 10-14 here).
  ASSERT_EQ(r.drift_by_age.size(), 3u);
  EXPECT_NEAR(r.drift_by_age[0].drift.mean_x, step * 2.5, 2e-3);   // ages 1..4
  EXPECT_NEAR(r.drift_by_age[1].drift.mean_x, step * 7.0, 2e-3);   // ages 5..9
  EXPECT_NEAR(r.drift_by_age[2].drift.mean_x, step * 12.0, 2e-3);  // ages 10..14
  // A shift, not an expansion: carried along by the flow's own deformation
  // (lens, perspective) it reads as a little one (-0.8 to -2.3e-5 here),
  // far below what a per-step expansion of 1e-4 accumulates (next test).
  for (const AgeBin& bin : r.drift_by_age) EXPECT_LT(std::fabs(bin.drift_expansion), 5e-5) << bin.from;
}

TEST(TrackTruth, MeasuresASpuriousExpansion) {
  const Flight& f = flight();
  const SimScene scene = scene_of(f);
  std::vector<tracks_t> tracks = tracks_along(scene, f, 0.0, 1e-4);
  TrackTruth compare(scene, estimator_camera());
  for (tracks_t& t : tracks) compare.process(&t, Rewrite::kNone);
  const TrackTruthReport r = compare.report();
  EXPECT_NEAR(r.flow_expansion_per_frame, 1e-4, 1e-6);
  EXPECT_NEAR(r.flow.mean_x, 0.0, 5e-3);
  // The drift accumulates it: age a has expanded by about a * 1e-4.
  ASSERT_EQ(r.drift_by_age.size(), 3u);
  EXPECT_NEAR(r.drift_by_age[0].drift_expansion, 2.5e-4, 0.1e-4);   // ages 1..4
  EXPECT_NEAR(r.drift_by_age[1].drift_expansion, 7.0e-4, 0.2e-4);   // ages 5..9
  EXPECT_NEAR(r.drift_by_age[2].drift_expansion, 12.0e-4, 0.3e-4);  // ages 10..14
  for (const AgeBin& bin : r.drift_by_age) EXPECT_NEAR(bin.flow_expansion, 1e-4, 1e-6) << "every step's, " << bin.from;
}

TEST(TrackTruth, RewrittenTracksAreExactAndTheirNormalizedCoordinatesMatchTheirPixels) {
  const Flight& f = flight();
  const SimScene scene = scene_of(f);
  const CameraModel camera = estimator_camera();
  std::vector<tracks_t> tracks = tracks_along(scene, f, 0.05);
  TrackTruth rewrite(scene, camera);
  for (tracks_t& t : tracks) rewrite.process(&t, Rewrite::kExact);
  TrackTruth check(scene, camera);
  for (tracks_t& t : tracks) check.process(&t, Rewrite::kNone);
  const TrackTruthReport r = check.report();
  EXPECT_LT(r.flow.rms, 1e-3);
  for (const AgeBin& bin : r.drift_by_age) EXPECT_LT(bin.drift.rms, 1e-3) << bin.from;
  const tracks_t& t = tracks.back();
  ASSERT_GT(t.num_tracks, 0);
  for (int i = 0; i < t.num_tracks; ++i) {
    const auto n = camera.undistort({cv::Point2f(t.curr_px[i][0], t.curr_px[i][1])});
    EXPECT_DOUBLE_EQ(t.curr_norm[i][0], n[0].x);
    EXPECT_DOUBLE_EQ(t.curr_norm[i][1], n[0].y);
  }
}

TEST(TrackTruth, FlowRewriteKeepsTheDriftAndMakesEachStepExact) {
  const Flight& f = flight();
  const SimScene scene = scene_of(f);
  std::vector<tracks_t> tracks = tracks_along(scene, f, 0.05);
  const std::vector<tracks_t> before = tracks;
  TrackTruth rewrite(scene, estimator_camera());
  for (tracks_t& t : tracks) rewrite.process(&t, Rewrite::kFlow);
  TrackTruth check(scene, estimator_camera());
  for (tracks_t& t : tracks) check.process(&t, Rewrite::kNone);
  EXPECT_LT(check.report().flow.rms, 1e-3);
  for (size_t k = 0; k < tracks.size(); ++k) {
    for (int i = 0; i < tracks[k].num_tracks; ++i) {
      EXPECT_EQ(tracks[k].prev_px[i][0], before[k].prev_px[i][0]);
      EXPECT_EQ(tracks[k].prev_norm[i][1], before[k].prev_norm[i][1]);
    }
  }
}

TEST(TrackTruth, MessagesAwayFromAnyFrameTruthAreCountedNotCompared) {
  const Flight& f = flight();
  const SimScene scene = scene_of(f);
  std::vector<tracks_t> tracks = tracks_along(scene, f, 0.0);
  tracks[3].utime += 30000;  // 30 ms: beyond a quarter frame (18 ms at 14 Hz)
  const tracks_t shifted = tracks[3];
  TrackTruth compare(scene, estimator_camera());
  for (tracks_t& t : tracks) compare.process(&t, Rewrite::kExact);
  const TrackTruthReport r = compare.report();
  EXPECT_EQ(r.messages_without_truth, 1);
  EXPECT_EQ(tracks[3].curr_px, shifted.curr_px);  // left as tracked
}

TEST(TrackTruthTool, ALogWithoutTheSimulatorsConfigIsAClearError) {
  testing::TempDir dir("track_truth");
  {
    LogWriter w(dir.file("plain.lcmlog"));
    config_t c;
    c.utime = 1;
    c.name = "tracker";
    c.source = "x";
    c.yaml = "camera: {}\n";
    const std::vector<uint8_t> bytes = encode_message(c);
    w.write(1, channels::kConfig, bytes.data(), bytes.size());
  }
  const std::string command = std::string(NADIR_BINARY_DIR) + "/bin/nadir_track_truth --in " +
                              dir.file("plain.lcmlog") + " 2>" + dir.file("err") + " >/dev/null";
  const int status = std::system(command.c_str());
  EXPECT_NE(status, 0);
  const std::vector<uint8_t> err = testing::read_file_bytes(dir.file("err"));
  const std::string text(err.begin(), err.end());
  EXPECT_NE(text.find("plain.lcmlog"), std::string::npos) << text;
  EXPECT_NE(text.find("nadir_sim"), std::string::npos) << text;
}

}  // namespace
}  // namespace nadir::track_truth
