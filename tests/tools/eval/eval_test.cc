#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <fstream>
#include <iterator>
#include <map>
#include <random>

#include "common/channels.h"
#include "common/log_file.h"
#include "nadir/config_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/status_t.hpp"
#include "nadir/tracks_t.hpp"
#include "tests/common/test_support.h"
#include "tools/hostile/hostile_messages.h"
#include "tools/eval/eval_outputs.h"
#include "tools/eval/trajectory_metrics.h"

namespace nadir {
namespace {

template <class Msg>
void put(LogWriter& w, const std::string& channel, const Msg& m) {
  std::vector<uint8_t> buf(m.getEncodedSize());
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  w.write(m.utime, channel, buf.data(), buf.size());
}

// A straight flight north at 20 m/s for 100 s starting at an arbitrary
// offset; the estimate has a constant 1 % scale error and drifts 0.5 m east.
// `hole`: no messages at all from 30 s to 33 s (a logger stopped for 3 s).
// `pairs`: the VO solver's CONFIG (the default camera) and a VO_DELTA per
// pose after the first, each the truth step. `first`: writes what the log begins with.
void write_flight(const std::string& path, bool with_truth, bool hole = false, bool pairs = false,
                  const std::function<void(LogWriter&)>& first = {}) {
  LogWriter w(path);
  if (first) first(w);
  const int64_t t0 = 1767225600000000;
  if (pairs) {
    config_t c{};
    c.utime = t0;
    c.name = "vo_solver";
    c.source = "default.yaml";
    std::ifstream in(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
    c.yaml.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    put(w, channels::kConfig, c);
  }
  int64_t previous_pose = 0;
  for (int i = 0; i <= 10000; ++i) {  // truth at 100 Hz
    const int64_t utime = t0 + i * 10000;
    const double t = i * 0.01;
    if (hole && t >= 30.0 && t < 33.0) continue;
    if (with_truth) {
      ground_truth_t g{};
      g.utime = utime;
      g.kind = ground_truth_t::KIND_INS;
      g.position_ned[0] = 500.0 + 20.0 * t;
      g.position_ned[1] = -30.0;
      g.position_ned[2] = -300.0;
      g.height_agl_m = 300.0;
      g.velocity_ned[0] = 20.0;
      g.yaw = 0.0;
      put(w, channels::kGroundTruth, g);
    }
    if (i % 7 == 0 && i >= 100) {  // poses at ~14 Hz from t = 1 s
      pose_t p{};
      p.utime = utime;
      const double flown = 20.0 * (t - 1.0);
      p.position_ned[0] = 1.01 * flown;
      p.position_ned[1] = 0.5 * (t - 1.0) / 99.0;
      p.velocity_ned[0] = 20.2;
      p.yaw = 0.01;
      // Protection level, by pose number k: unavailable, 0 (always exceeded), 1 km (never).
      const int k = (i - 105) / 7;
      p.horizontal_protection_level_m = k % 4 == 0 ? -1.0 : (k % 4 == 1 ? 0.0 : 1000.0);
      put(w, channels::kPose, p);
      if (pairs && previous_pose != 0) {
        vo_delta_t d{};
        d.utime = utime;
        d.prev_utime = previous_pose;
        d.dx = 20.0 * 0.07;
        d.variant = "paper";
        put(w, channels::kVoDelta, d);
      }
      previous_pose = utime;
    }
  }
  w.flush();
}

TEST(Eval, MetricsMatchAKnownError) {
  testing::TempDir dir("eval");
  write_flight(dir.file("flight.lcmlog"), true);
  const EvalResult r = evaluate(load_eval_data(dir.file("flight.lcmlog"), ""));
  const EvalMetrics& m = r.metrics;
  const double flown = r.samples.back().truth[0];
  EXPECT_NEAR(m.distance_m, flown, 1e-6);
  EXPECT_NEAR(flown, 20.0 * (99.96 - 1.05), 1e-6);  // first pose at i = 105, last at 9996
  const double expected_h = std::hypot(0.01 * flown, 0.5 * (flown / 20.0) / 99.0);
  EXPECT_NEAR(m.final_error_h_m, expected_h, 1e-6);
  EXPECT_NEAR(m.error_pct_h, 100.0 * expected_h / flown, 1e-6);
  EXPECT_NEAR(m.final_error_v_m, 0.0, 1e-9);
  EXPECT_NEAR(m.rms_velocity_error_h, 0.2, 1e-9);
  EXPECT_NEAR(m.rms_yaw_error_deg, 0.01 * 180 / M_PI, 1e-9);
  // The error over the whole flight, from the known error at each pose's distance.
  double sum_sq = 0;
  for (const EvalSample& s : r.samples) sum_sq += std::pow(std::hypot(0.01 * s.truth[0], s.truth[0] / 3960.0), 2);
  const double expected_rms = std::sqrt(sum_sq / static_cast<double>(r.samples.size()));
  EXPECT_NEAR(m.rms_error_h_m, expected_rms, 1e-6);
  EXPECT_NEAR(m.rms_error_3d_m, expected_rms, 1e-6);
  EXPECT_NEAR(m.rms_error_pct_3d, 100.0 * expected_rms / flown, 1e-6);
  EXPECT_LT(m.rms_error_h_m, m.final_error_h_m);  // the error grows linearly: its rms is below its end
  // Protection level: the first pose (the origin) has no statement; of the
  // others every fourth is unavailable, one in three of the rest exceeded.
  const int64_t poses = static_cast<int64_t>(r.samples.size());
  int64_t unavailable = 0, exceeded = 0;
  for (int64_t k = 1; k < poses; ++k) {
    unavailable += k % 4 == 0;
    exceeded += k % 4 == 1;
  }
  EXPECT_EQ(m.pl_unavailable, unavailable);
  EXPECT_EQ(m.pl_samples, poses - 1 - unavailable);
  EXPECT_NEAR(m.pl_exceeded_pct, 100.0 * static_cast<double>(exceeded) / static_cast<double>(poses - 1 - unavailable),
              1e-9);
  EXPECT_EQ(r.samples[1].protection_level_m, 0.0);
  EXPECT_EQ(r.samples[2].protection_level_m, 1000.0);
}

TEST(Eval, PairFootprintsFromTheSolversCamera) {
  testing::TempDir dir("eval");
  write_flight(dir.file("without.lcmlog"), true);
  const EvalMetrics without = evaluate(load_eval_data(dir.file("without.lcmlog"), "")).metrics;
  EXPECT_EQ(without.pairs_overlapping_solved_pct, -1.0);
  write_flight(dir.file("pairs.lcmlog"), true, false, true);
  const EvalResult r = evaluate(load_eval_data(dir.file("pairs.lcmlog"), ""));
  EXPECT_TRUE(r.metrics.footprint_problem.empty()) << r.metrics.footprint_problem;
  ASSERT_GT(r.metrics.pairs, 1000);
  EXPECT_EQ(r.metrics.pairs_apart, 0);
  EXPECT_NEAR(r.metrics.pairs_overlapping_solved_pct, 100.0, 1e-9);
  // 1.4 m between frames at 300 m: almost the whole footprint is seen again.
  for (const PairSample& s : r.pairs.samples) EXPECT_GT(s.overlap_pct, 98.0);
  EXPECT_NEAR(r.metrics.pair_error_pct_median, 0.0, 1e-6);
}

TEST(Eval, AFirstFrameExposedJustBeforeTheTruthStartsIsStillTheOrigin) {
  // The simulator's first frame is exposed 30 us before its first truth
  // sample. That pose is POSE's origin; the second one already carries the
  // first pair's error, here (0.5, -1.0) m, which every later pose keeps. An
  // evaluation anchored at the second pose would call the flight perfect.
  testing::TempDir dir("eval_first_frame");
  {
    LogWriter w(dir.file("flight.lcmlog"));
    const int64_t t0 = 1767225600000000;
    for (int i = 0; i <= 1000; ++i) {  // truth at 100 Hz for 10 s
      ground_truth_t g{};
      g.utime = t0 + i * 10000;
      g.kind = ground_truth_t::KIND_INS;
      g.position_ned[0] = 100.0 + 20.0 * i * 0.01;
      g.position_ned[2] = -150.0;
      g.velocity_ned[0] = 20.0;
      g.height_agl_m = 150.0;
      put(w, channels::kGroundTruth, g);
    }
    for (int k = 0; k < 100; ++k) {  // poses at 10 Hz from 30 us before the truth
      pose_t p{};
      p.utime = t0 - 30 + k * 100000;
      const double flown = 20.0 * static_cast<double>(p.utime - (t0 - 30)) * 1e-6;
      p.position_ned[0] = flown + (k > 0 ? 0.5 : 0.0);
      p.position_ned[1] = k > 0 ? -1.0 : 0.0;
      p.velocity_ned[0] = k > 0 ? 20.0 : 0.0;  // the origin has no velocity yet
      put(w, channels::kPose, p);
    }
    w.flush();
  }
  const EvalResult r = evaluate(load_eval_data(dir.file("flight.lcmlog"), ""));
  ASSERT_EQ(r.samples.size(), 100u);
  EXPECT_EQ(r.samples[0].error_h_m, 0.0);
  EXPECT_NEAR(r.samples[1].error_h_m, std::hypot(0.5, 1.0), 1e-6);
  EXPECT_NEAR(r.metrics.final_error_h_m, std::hypot(0.5, 1.0), 1e-6);
  EXPECT_NEAR(r.metrics.distance_m, 20.0 * 9.9, 1e-6);
  EXPECT_NEAR(r.metrics.rms_velocity_error_h, 0.0, 1e-9);  // the origin's velocity is no estimate
  EXPECT_NEAR(r.metrics.max_velocity_error_h, 0.0, 1e-9);
}

TEST(Eval, TruthFromASeparateLog) {
  testing::TempDir dir("eval");
  write_flight(dir.file("truth.lcmlog"), true);
  write_flight(dir.file("poses.lcmlog"), false);
  const EvalResult r = evaluate(load_eval_data(dir.file("poses.lcmlog"), dir.file("truth.lcmlog")));
  EXPECT_GT(r.metrics.poses, 1000);
  write_series_csv(r, dir.file("series.csv"));
  write_geojson(r, dir.file("t.geojson"));
  write_kml(r, dir.file("t.kml"));
  const auto csv = testing::read_file_bytes(dir.file("series.csv"));
  EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 1000);
  const auto geo = testing::read_file_bytes(dir.file("t.geojson"));
  EXPECT_NE(std::string(geo.begin(), geo.end()).find("LineString"), std::string::npos);
}

// A reported covariance with a north-east term: series.csv carries it
// (cov_ne_m2), and the horizontal NEES is the 2-D one it implies.
TEST(Eval, SeriesCarriesTheNorthEastCovariance) {
  testing::TempDir dir("eval");
  {
    LogWriter w(dir.file("flight.lcmlog"));
    const int64_t t0 = 1767225600000000;
    for (int i = 0; i <= 200; ++i) {
      const int64_t utime = t0 + i * 100000;
      ground_truth_t g{};
      g.utime = utime;
      g.kind = ground_truth_t::KIND_INS;
      g.position_ned[0] = 2.0 * i;
      g.position_ned[2] = -300.0;
      g.height_agl_m = 300.0;
      put(w, channels::kGroundTruth, g);
      pose_t p{};
      p.utime = utime;
      p.position_ned[0] = 2.0 * i + (i > 0 ? 1.0 : 0.0);  // 1 m north, 1 m east off after the origin
      p.position_ned[1] = i > 0 ? 1.0 : 0.0;
      p.position_covariance[0][0] = 4.0;
      p.position_covariance[1][1] = 1.0;
      p.position_covariance[0][1] = p.position_covariance[1][0] = 1.5;
      put(w, channels::kPose, p);
    }
    w.flush();
  }
  const EvalResult r = evaluate(load_eval_data(dir.file("flight.lcmlog"), ""));
  const EvalSample& last = r.samples.back();
  EXPECT_DOUBLE_EQ(last.cov_ne_m2, 1.5);
  // e = (1, 1), P = [[4, 1.5], [1.5, 1]]: e' P^-1 e = (1 - 3 + 4) / (4 - 2.25).
  EXPECT_NEAR(last.nees_h, 2.0 / 1.75, 1e-12);
  write_series_csv(r, dir.file("series.csv"));
  std::ifstream in(dir.file("series.csv"));
  std::string header, row, final_row;
  std::getline(in, header);
  while (std::getline(in, row)) final_row = row;
  EXPECT_EQ(header.substr(header.rfind(',') + 1), "cov_ne_m2");
  EXPECT_EQ(final_row.substr(final_row.rfind(',') + 1), "1.5");
}

TEST(Eval, ACaptureHoleAndATruncatedLogAreReported) {
  testing::TempDir dir("eval");
  write_flight(dir.file("clean.lcmlog"), true);
  const EvalData clean = load_eval_data(dir.file("clean.lcmlog"), "");
  EXPECT_TRUE(clean.holes.empty());
  EXPECT_FALSE(clean.truncated);

  write_flight(dir.file("holed.lcmlog"), true, true);
  const EvalData holed = load_eval_data(dir.file("holed.lcmlog"), "");
  ASSERT_EQ(holed.holes.size(), 2u);  // GROUND_TRUTH and POSE
  for (const LogHole& h : holed.holes) {
    // Last message before the hole to the first after it: 29.99 -> 33.00 s at
    // 100 Hz, 29.96 -> 33.04 s for the poses at every 7th step.
    EXPECT_NEAR(h.seconds(), h.channel == channels::kPose ? 3.08 : 3.01, 1e-9) << h.channel;
    EXPECT_EQ(h.from_timestamp, 1767225600000000 + (h.channel == channels::kPose ? 2996 : 2999) * 10000) << h.channel;
  }
  EXPECT_EQ(holed.holes[0].channel, channels::kGroundTruth);
  // ~300 missing at 100 Hz, estimated from the mean interval (which the hole itself lengthens).
  EXPECT_NEAR(holed.holes[0].expected_messages, 290, 1);
  const EvalResult r = evaluate(holed);
  EXPECT_EQ(r.metrics.capture_holes, 2);
  EXPECT_NEAR(r.metrics.capture_hole_seconds, 3.08, 1e-9);
  EXPECT_NE(format_log_holes(holed.holes).find("GROUND_TRUTH: no messages for 3.010 s"), std::string::npos)
      << format_log_holes(holed.holes);

  std::vector<uint8_t> bytes = testing::read_file_bytes(dir.file("clean.lcmlog"));
  bytes.resize(bytes.size() - 40);
  testing::write_file_bytes(dir.file("cut.lcmlog"), bytes);
  const EvalData cut = load_eval_data(dir.file("cut.lcmlog"), "");
  EXPECT_TRUE(cut.truncated);
  EXPECT_NE(cut.damage_report.find("cut.lcmlog: byte"), std::string::npos) << cut.damage_report;
}

// 100 frames at 14 Hz through the whole pipeline (CAMERA_IMAGE, TRACKS,
// VO_DELTA, POSE logged 5, 20, 30 and 40 ms after the frame's sensor time)
// with nadir_hostile's messages among them at 20 Hz, every case in turn.
// Returns how many hostile records went on CAMERA_IMAGE, TRACKS and VO_DELTA.
int64_t write_flight_with_a_second_publisher(const std::string& path) {
  LogWriter w(path);
  auto put_at = [&](const std::string& channel, const auto& m, int64_t logged) {
    std::vector<uint8_t> buf(static_cast<size_t>(m.getEncodedSize()));
    m.encode(buf.data(), 0, static_cast<int>(buf.size()));
    w.write(logged, channel, buf.data(), buf.size());
  };
  const int64_t t0 = 1767225600000000, period = 71429;
  std::mt19937_64 rng(3);
  int64_t hostile_on_frame_channels = 0;
  size_t hostile_index = 0;
  int64_t next_hostile = t0;
  for (int k = 0; k < 100; ++k) {
    const int64_t t = t0 + k * period;
    ground_truth_t g{};
    g.utime = t;
    g.kind = ground_truth_t::KIND_INS;
    g.position_ned[0] = 20.0 * k * period * 1e-6;
    g.velocity_ned[0] = 20.0;
    put_at(channels::kGroundTruth, g, t);
    image_t image{};
    image.utime = image.trigger_utime = t;
    image.frame_counter = k;
    image.width = 64;
    image.height = 48;
    image.stride = 64;
    image.pixel_format = image_t::PIXEL_MONO8;
    image.size = 64 * 48;
    image.data.assign(64 * 48, 100);
    put_at(channels::kCameraImage, image, t + 5000);
    tracks_t tracks{};
    tracks.utime = t;
    tracks.prev_utime = k > 0 ? t - period : 0;
    tracks.frame_counter = k;
    put_at(channels::kTracks, tracks, t + 20000);
    {
      vo_delta_t d{};  // the solver's answer to the first frame has no previous one
      d.utime = t;
      d.prev_utime = k > 0 ? t - period : 0;
      d.dx = 20.0 * period * 1e-6;
      d.variant = "paper";
      put_at(channels::kVoDelta, d, t + 30000);
    }
    pose_t p{};
    p.utime = t;
    p.position_ned[0] = g.position_ned[0];
    p.velocity_ned[0] = 20.0;
    put_at(channels::kPose, p, t + 40000);
    for (; next_hostile < t + period; next_hostile += 50000) {
      const HostileMessage m = hostile_message(hostile_index++, next_hostile, 64, 48, rng);
      w.write(next_hostile, m.channel, m.bytes.data(), m.bytes.size());
      if (m.channel == channels::kCameraImage || m.channel == channels::kTracks || m.channel == channels::kVoDelta) {
        ++hostile_on_frame_channels;
      }
    }
  }
  w.flush();
  return hostile_on_frame_channels;
}

// A second publisher's images, tracks and deltas are neither frames nor
// latency: the figures are the pipeline's alone.
TEST(Eval, RecordsTheTrackerDidNotAnswerAreNeitherFramesNorLatency) {
  testing::TempDir dir("eval");
  const int64_t hostile = write_flight_with_a_second_publisher(dir.file("hostile.lcmlog"));
  ASSERT_GT(hostile, 50);
  const EvalData data = load_eval_data(dir.file("hostile.lcmlog"), "");
  EXPECT_EQ(data.pipeline.frames, 100);
  EXPECT_EQ(data.pipeline.tracks, 100);
  EXPECT_EQ(data.pipeline.vo_deltas, 100);
  EXPECT_EQ(data.pipeline.other_images + data.pipeline.other_tracks + data.pipeline.other_vo_deltas, hostile);
  EXPECT_GT(data.pipeline.other_images, 0);
  EXPECT_GT(data.pipeline.other_tracks, 0);
  EXPECT_GT(data.pipeline.other_vo_deltas, 0);
  ASSERT_EQ(data.deltas.size(), 100u);
  for (const vo_delta_t& d : data.deltas) EXPECT_NEAR(d.dx, 20.0 * 0.071429, 1e-9);
  const std::map<std::string, float> logged_after = {
      {channels::kCameraImage, 5.f}, {channels::kTracks, 20.f}, {channels::kVoDelta, 30.f}, {channels::kPose, 40.f}};
  for (const auto& [channel, ms] : logged_after) {
    const auto it = data.stage_latency_ms.find(channel);
    ASSERT_NE(it, data.stage_latency_ms.end()) << channel;
    EXPECT_EQ(it->second.size(), 100u) << channel;
    for (float v : it->second) EXPECT_FLOAT_EQ(v, ms) << channel;
  }
  ASSERT_EQ(data.after_image_latency_ms.size(), 100u);
  for (float v : data.after_image_latency_ms) EXPECT_FLOAT_EQ(v, 35.f);
  const EvalMetrics m = evaluate(data).metrics;
  EXPECT_EQ(m.images, 100);
  EXPECT_EQ(m.records_not_pipeline, hostile);
  EXPECT_EQ(m.pairs, 99);
  EXPECT_FLOAT_EQ(static_cast<float>(m.latency_max_ms), 40.f);
  EXPECT_FLOAT_EQ(static_cast<float>(m.after_image_latency_max_ms), 35.f);
}

TEST(Eval, LogWithoutTruthOrPoseGetsAClearError) {
  testing::TempDir dir("eval");
  write_flight(dir.file("poses.lcmlog"), false);
  try {
    load_eval_data(dir.file("poses.lcmlog"), "");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no GROUND_TRUTH"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("poses.lcmlog"), std::string::npos);
  }
  LogWriter(dir.file("empty.lcmlog")).flush();
  try {
    load_eval_data(dir.file("empty.lcmlog"), "");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no POSE"), std::string::npos);
  }
}

// Where a log comes from decides what its report can say: latency only from
// a live capture (a lockstep replay's STATUS carries pid 0, its log times are
// the input's), and an import's truth is the flight's own record. The VO
// solver's CONFIG gives the reject mask the pairs are judged with.
void write_origin(LogWriter& w, const std::string& config_name, const std::string& yaml, int32_t pid) {
  const int64_t t0 = 1767225600000000;
  if (!config_name.empty()) {
    config_t c{};
    c.utime = t0;
    c.name = config_name;
    c.yaml = yaml;
    put(w, channels::kConfig, c);
  }
  status_t s{};
  s.utime = t0;
  s.name = "yaw_fusion";
  s.pid = pid;
  put(w, channels::kStatus, s);
}

TEST(Eval, LatencyOnlyForALiveCaptureAndImportsSaySo) {
  testing::TempDir dir("eval");
  struct Case {
    const char* name;
    std::string config;
    int32_t pid;
    bool latency;
    bool imported;
  };
  for (const Case& c : {Case{"live", "", 4242, true, false}, Case{"replay", "", 0, false, false},
                        Case{"import", "import", 0, false, true}, Case{"live_import", "import", 4242, false, true}}) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.file(std::string(c.name) + ".lcmlog");
    write_flight(path, true, false, false, [&](LogWriter& w) { write_origin(w, c.config, "mode: photos\n", c.pid); });
    const EvalData data = load_eval_data(path, "");
    const EvalMetrics m = evaluate(data).metrics;
    EXPECT_EQ(m.latency_measured, c.latency);
    EXPECT_EQ(m.imported, c.imported);
    EXPECT_EQ(data.photo_intervals.empty(), !c.imported);
  }
}

TEST(Eval, PairsAreJudgedWithTheConfiguredRejectMask) {
  testing::TempDir dir("eval");
  const std::string path = dir.file("flight.lcmlog");
  write_flight(path, true, false, true);
  EvalData data = load_eval_data(path, "");
  ASSERT_GT(data.deltas.size(), 10u);
  data.deltas[3].quality = vo_delta_t::QUALITY_HEADING_CONTRADICTS;
  data.deltas[5].quality = vo_delta_t::QUALITY_HEADING_CONTRADICTS | vo_delta_t::QUALITY_HIGH_RESIDUAL;
  const EvalMetrics m = evaluate(data).metrics;  // the shipped config: 283
  EXPECT_EQ(m.pairs_solved, m.pairs - 2);
  EXPECT_EQ(m.pairs_not_solved_flagged, 2);
  EXPECT_EQ(m.pairs_heading_contradicts, 2);
  EXPECT_EQ(m.pairs_not_solved_why, "2 heading_contradicts");

  const std::string shipped = "reject_quality_mask: 283";
  ASSERT_NE(data.estimator_config_yaml.find(shipped), std::string::npos);
  data.estimator_config_yaml.replace(data.estimator_config_yaml.find(shipped), shipped.size(), "reject_quality_mask: 27");
  const EvalMetrics old_mask = evaluate(data).metrics;
  EXPECT_EQ(old_mask.pairs_solved, old_mask.pairs);
  EXPECT_EQ(old_mask.pairs_not_solved_flagged, 0);
}

}  // namespace
}  // namespace nadir
