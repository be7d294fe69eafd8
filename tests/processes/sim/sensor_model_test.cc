// Each sensor model's noise matches its configured sigma within sampling error.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "common/channels.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/trigger_t.hpp"
#include "processes/sim/sim_rotation.h"
#include "processes/sim/simulator.h"
#include "sim_test_support.h"

namespace nadir::sim {
namespace {

template <class Msg>
Msg decode(const SimEvent& e) {
  Msg m;
  EXPECT_EQ(m.decode(e.data.data(), 0, static_cast<int>(e.data.size())), static_cast<int>(e.data.size()));
  return m;
}

struct Stats {
  double sum = 0, sum2 = 0;
  int64_t n = 0;
  void add(double x) {
    sum += x;
    sum2 += x * x;
    ++n;
  }
  double mean() const { return sum / n; }
  double stddev() const { return std::sqrt(sum2 / n - mean() * mean()); }
};

// A sample stddev of n Gaussian draws has relative standard error 1/sqrt(2n);
// 4 of those is the tolerance.
double tolerance(int64_t n) { return 4.0 / std::sqrt(2.0 * static_cast<double>(n)); }

class SensorNoise : public ::testing::Test {
 protected:
  void run(const SensorOptions& sensors, uint64_t seed) {
    SimulatorOptions options;
    options.seed = seed;
    options.render_images = false;
    Simulator sim(testing::profile("test1"), testing::default_camera(), sensors, options);
    std::map<int64_t, ground_truth_t> truth_at;  // KIND_INS truth by utime
    SimEvent e;
    while (sim.next(&e)) {
      if (e.channel == channels::kGroundTruth) {
        const auto gt = decode<ground_truth_t>(e);
        if (gt.kind == ground_truth_t::KIND_INS) truth_at[gt.utime] = gt;
        if (gt.kind == ground_truth_t::KIND_FRAME) frame_truth.push_back(gt);
      } else if (e.channel == channels::kIns) {
        ins.push_back(decode<ins_t>(e));
      } else if (e.channel == channels::kAltimeter) {
        const auto a = decode<altimeter_t>(e);
        altimeter.push_back(a);
        double range = 0;
        ASSERT_TRUE(sim.altimeter_truth_range((a.utime - options.epoch_us) * 1e-6, &range));
        altimeter_truth.push_back(range);
      } else if (e.channel == channels::kCameraTrigger) {
        triggers.push_back(decode<trigger_t>(e));
      }
    }
    for (const ins_t& m : ins) {
      auto it = truth_at.find(m.utime);  // INS and its truth share the sample time
      ASSERT_NE(it, truth_at.end());
      ins_truth.push_back(it->second);
    }
    epoch = options.epoch_us;
    counts = sim.counts();
    rate_hz = sim.camera().rate_hz;
  }
  std::vector<ins_t> ins;
  std::vector<ground_truth_t> ins_truth;
  std::vector<altimeter_t> altimeter;
  std::vector<double> altimeter_truth;
  std::vector<trigger_t> triggers;
  std::vector<ground_truth_t> frame_truth;
  int64_t epoch = 0;
  SimulatorCounts counts;
  double rate_hz = 14.0;
};

TEST_F(SensorNoise, StandardSetMatchesItsSigmas) {
  const SensorOptions sensors = testing::sensor_set("standard");
  run(sensors, 21);
  ASSERT_EQ(ins.size(), ins_truth.size());
  ASSERT_GT(ins.size(), 25000u);  // 100 Hz over 260 s

  Stats roll, pitch, yaw_diff;
  double previous_yaw_error = 0;
  for (size_t i = 0; i < ins.size(); ++i) {
    roll.add(ins[i].roll - ins_truth[i].roll);
    pitch.add(ins[i].pitch - ins_truth[i].pitch);
    const double yaw_error = wrap_pi(ins[i].yaw - ins_truth[i].yaw);
    // Successive differences cancel the slow bias: var = 2 sigma^2 (+ tiny walk).
    if (i > 0) yaw_diff.add(yaw_error - previous_yaw_error);
    previous_yaw_error = yaw_error;
    EXPECT_EQ(ins[i].flags, ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD | ins_t::FLAG_SIMULATED);
    EXPECT_TRUE(ins[i].has_stddev);
  }
  const double rp = deg2rad(sensors.ins.roll_pitch_noise_deg), yw = deg2rad(sensors.ins.yaw_noise_deg);
  EXPECT_NEAR(roll.stddev() / rp, 1.0, tolerance(roll.n));
  EXPECT_NEAR(pitch.stddev() / rp, 1.0, tolerance(pitch.n));
  EXPECT_NEAR(roll.mean(), 0.0, 4.0 * rp / std::sqrt(roll.n));
  EXPECT_NEAR(yaw_diff.stddev() / (std::sqrt(2.0) * yw), 1.0, 2.0 * tolerance(yaw_diff.n));
  EXPECT_DOUBLE_EQ(ins.front().attitude_stddev[0], rp);
  EXPECT_DOUBLE_EQ(ins.front().attitude_stddev[2], yw);
  // The bias drifts but slowly: the error averaged over the last 10 s stays
  // within a few random-walk sigmas of zero.
  Stats tail;
  for (size_t i = ins.size() - 1000; i < ins.size(); ++i) tail.add(wrap_pi(ins[i].yaw - ins_truth[i].yaw));
  const double walk_sigma = deg2rad(sensors.ins.yaw_bias_walk_deg_per_sqrt_s) * std::sqrt(260.0);
  EXPECT_LT(std::fabs(tail.mean()), 5.0 * walk_sigma + 4.0 * yw / std::sqrt(1000.0));

  // Altimeter: normalised residuals have unit sigma; dropouts flagged.
  Stats normalized;
  int64_t dropouts = 0;
  for (size_t i = 0; i < altimeter.size(); ++i) {
    const altimeter_t& a = altimeter[i];
    EXPECT_NEAR(a.beam_body[2], 1.0, 1e-12);
    if (a.validity == altimeter_t::VALID_NO_RETURN) {
      ++dropouts;
      continue;
    }
    ASSERT_EQ(a.validity, altimeter_t::VALID_OK);
    const double sigma = sensors.altimeter.noise_m + 0.01 * sensors.altimeter.noise_pct * altimeter_truth[i];
    normalized.add((a.range_m - altimeter_truth[i]) / sigma);
  }
  ASSERT_GT(altimeter.size(), 2500u);
  EXPECT_NEAR(normalized.stddev(), 1.0, tolerance(normalized.n));
  EXPECT_NEAR(normalized.mean(), 0.0, 4.0 / std::sqrt(normalized.n));
  const double expected_dropouts = sensors.altimeter.dropout_probability * altimeter.size();
  EXPECT_NEAR(dropouts, expected_dropouts, 4.0 * std::sqrt(expected_dropouts) + 1);
  EXPECT_EQ(dropouts, counts.altimeter_dropouts);

  // Trigger jitter: reported minus true exposure time (k / rate).
  Stats jitter;
  for (const trigger_t& t : triggers) {
    const int64_t true_us = std::llround(t.sequence * 1e6 / rate_hz);
    jitter.add(static_cast<double>(t.utime - epoch - true_us));
  }
  ASSERT_GT(triggers.size(), 3600u);
  EXPECT_NEAR(jitter.stddev() / sensors.camera.trigger_jitter_us, 1.0, tolerance(jitter.n) + 0.01);  // + rounding to 1 us
  const double expected_drops = sensors.camera.frame_drop_probability * triggers.size();
  EXPECT_NEAR(counts.dropped_frames, expected_drops, 4.0 * std::sqrt(expected_drops) + 1);
}

TEST_F(SensorNoise, NoiseStudyOverridesTakeEffect) {
  SensorOptions sensors = testing::sensor_set("standard");
  sensors.ins.roll_pitch_noise_deg = 0.5;
  sensors.ins.yaw_noise_deg = 1.0;
  sensors.altimeter.noise_pct = 2.0;
  sensors.altimeter.noise_m = 0.0;
  run(sensors, 3);
  Stats roll, alt;
  for (size_t i = 0; i < ins.size(); ++i) roll.add(ins[i].roll - ins_truth[i].roll);
  for (size_t i = 0; i < altimeter.size(); ++i)
    if (altimeter[i].validity == altimeter_t::VALID_OK)
      alt.add((altimeter[i].range_m - altimeter_truth[i]) / altimeter_truth[i]);
  EXPECT_NEAR(roll.stddev() / deg2rad(0.5), 1.0, tolerance(roll.n));
  EXPECT_NEAR(alt.stddev() / 0.02, 1.0, tolerance(alt.n));
}

TEST_F(SensorNoise, IdealSetIsNoiseFree) {
  run(testing::sensor_set("ideal"), 5);
  for (size_t i = 0; i < ins.size(); i += 97) {
    EXPECT_DOUBLE_EQ(ins[i].roll, ins_truth[i].roll);
    EXPECT_NEAR(ins[i].yaw, ins_truth[i].yaw, 1e-12);
  }
  for (size_t i = 0; i < altimeter.size(); ++i) EXPECT_NEAR(altimeter[i].range_m, altimeter_truth[i], 1e-9);
  EXPECT_EQ(counts.dropped_frames, 0);
}

// Autocorrelation of x at a lag of `lag` samples.
double autocorrelation(const std::vector<double>& x, size_t lag) {
  double num = 0, den = 0;
  for (size_t i = 0; i + lag < x.size(); ++i) num += x[i] * x[i + lag];
  for (double v : x) den += v * v;
  return num / den * static_cast<double>(x.size()) / static_cast<double>(x.size() - lag);
}

// Gauss-Markov roll/pitch/yaw errors alone (white noise and bias walk off):
// stationary sigma, the exact one-step recursion and the correlation time.
TEST_F(SensorNoise, GaussMarkovAttitudeErrorsMatchSigmaAndCorrelationTime) {
  SensorOptions sensors = testing::sensor_set("standard");
  sensors.ins.roll_pitch_noise_deg = 0.0;
  sensors.ins.yaw_noise_deg = 0.0;
  sensors.ins.yaw_bias_walk_deg_per_sqrt_s = 0.0;
  sensors.ins.roll_pitch_gm_sigma_deg = 0.2;
  sensors.ins.roll_pitch_gm_tau_s = 0.25;
  sensors.ins.yaw_gm_sigma_deg = 0.3;
  sensors.ins.yaw_gm_tau_s = 0.2;
  run(sensors, 17);
  ASSERT_GT(ins.size(), 25000u);
  std::vector<double> roll, pitch, yaw;
  for (size_t i = 0; i < ins.size(); ++i) {
    roll.push_back(ins[i].roll - ins_truth[i].roll);
    pitch.push_back(ins[i].pitch - ins_truth[i].pitch);
    yaw.push_back(wrap_pi(ins[i].yaw - ins_truth[i].yaw));
  }
  const double dt = 1.0 / sensors.ins.rate_hz;
  struct Axis {
    const std::vector<double>* x;
    double sigma, tau;
  };
  for (const Axis& axis : {Axis{&roll, deg2rad(0.2), 0.25}, Axis{&pitch, deg2rad(0.2), 0.25},
                           Axis{&yaw, deg2rad(0.3), 0.2}}) {
    const std::vector<double>& x = *axis.x;
    // Stationary sigma: about T / (2 tau) independent variance samples.
    Stats all;
    for (double v : x) all.add(v);
    const double n_eff = x.size() * dt / (2.0 * axis.tau);
    EXPECT_NEAR(std::sqrt(all.sum2 / all.n) / axis.sigma, 1.0, tolerance(static_cast<int64_t>(n_eff)));
    // The driving noise x[k+1] - a x[k] is white with sigma sqrt(1 - a^2).
    const double a = std::exp(-dt / axis.tau);
    Stats drive;
    std::vector<double> innovations;
    for (size_t i = 0; i + 1 < x.size(); ++i) {
      innovations.push_back(x[i + 1] - a * x[i]);
      drive.add(innovations.back());
    }
    EXPECT_NEAR(drive.stddev() / (axis.sigma * std::sqrt(1.0 - a * a)), 1.0, tolerance(drive.n));
    EXPECT_NEAR(autocorrelation(innovations, 1), 0.0, 4.0 / std::sqrt(static_cast<double>(drive.n)));
    // Correlation time: the autocorrelation at a lag of tau is 1/e (Bartlett
    // standard error of r at that lag ~0.02 here; 4 of those).
    const size_t lag = static_cast<size_t>(std::llround(axis.tau / dt));
    EXPECT_NEAR(autocorrelation(x, lag), std::exp(-1.0), 0.08);
  }
}

// The calibration-test set: the altimeter reads scale * range + bias (+ its
// noise), frames are exposed the time offset after their stamp, and the true
// camera carries the boresight while the estimator's config does not.
TEST_F(SensorNoise, InstallationErrorsOfTheCalibrationSet) {
  const SensorOptions sensors = testing::sensor_set("calibration_test");
  ASSERT_DOUBLE_EQ(sensors.altimeter.scale, 1.01);
  run(sensors, 9);
  Stats normalized;
  double sxx = 0, sxy = 0, sx = 0, sy = 0;
  int64_t n = 0;
  for (size_t i = 0; i < altimeter.size(); ++i) {
    if (altimeter[i].validity != altimeter_t::VALID_OK) continue;
    const double truth = altimeter_truth[i];
    const double sigma = sensors.altimeter.noise_m + 0.01 * sensors.altimeter.noise_pct * truth;
    normalized.add((altimeter[i].range_m - sensors.altimeter.scale * truth - sensors.altimeter.bias_m) / sigma);
    sxx += truth * truth, sxy += truth * altimeter[i].range_m, sx += truth, sy += altimeter[i].range_m, ++n;
  }
  EXPECT_NEAR(normalized.stddev(), 1.0, tolerance(normalized.n));
  EXPECT_NEAR(normalized.mean(), 0.0, 4.0 / std::sqrt(normalized.n));
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  EXPECT_NEAR(slope, 1.01, 0.002);

  // Frame truth (true exposure) minus trigger stamp = offset + latency + jitter.
  std::map<int64_t, int64_t> trigger_us;
  for (const trigger_t& t : triggers) trigger_us[t.sequence] = t.utime;
  ASSERT_EQ(frame_truth.size(), triggers.size());
  Stats delay;
  for (size_t k = 0; k < frame_truth.size(); ++k) delay.add(static_cast<double>(frame_truth[k].utime - trigger_us[k]));
  EXPECT_NEAR(delay.mean(), sensors.camera.exposure_delay_us(), 4.0 * sensors.camera.trigger_jitter_us / std::sqrt(delay.n));
  EXPECT_NEAR(delay.stddev() / sensors.camera.trigger_jitter_us, 1.0, tolerance(delay.n) + 0.01);
}

TEST(InstallationErrors, TrueCameraAndAltimeterBeamDifferFromTheConfig) {
  SensorOptions sensors = testing::sensor_set("calibration_test");
  sensors.camera.focal_scale = 1.01;
  sensors.camera.distortion_error = {0.01, 0, 0, 0, 0};
  sensors.altimeter.beam_misalignment_deg = {3.0, 0.0};
  SimulatorOptions options;
  options.render_images = false;
  const SimCamera configured = testing::default_camera();
  Simulator sim(testing::profile("test1"), configured, sensors, options);
  const Eigen::Matrix3d boresight =
      sim.configured_camera().body_from_camera.transpose() * sim.camera().body_from_camera;
  EXPECT_NEAR(boresight(2, 1), deg2rad(0.4), 1e-4);   // roll: camera y toward z
  EXPECT_NEAR(boresight(0, 2), deg2rad(-0.3), 1e-4);  // pitch
  EXPECT_NEAR(boresight(1, 0), deg2rad(0.5), 1e-4);   // yaw
  EXPECT_DOUBLE_EQ(sim.camera().fx, configured.fx * 1.01);
  EXPECT_DOUBLE_EQ(sim.camera().distortion[0], configured.distortion[0] + 0.01);
  EXPECT_DOUBLE_EQ(sim.configured_camera().fx, configured.fx);
  // A beam misaligned by 3 deg in roll reads longer than the nominal one at
  // the same instant over gently rolling terrain: about 1/cos(3 deg) on average.
  SensorOptions aligned = sensors;
  aligned.altimeter.beam_misalignment_deg = {0.0, 0.0};
  Simulator reference(testing::profile("test1"), configured, aligned, options);
  Stats ratio;
  for (double t = 10; t < 250; t += 0.5) {
    double r1 = 0, r0 = 0;
    if (sim.altimeter_truth_range(t, &r1) && reference.altimeter_truth_range(t, &r0)) ratio.add(r1 / r0);
  }
  ASSERT_GT(ratio.n, 400);
  EXPECT_GT(ratio.stddev(), 1e-5);  // really a different ray
  EXPECT_NEAR(ratio.mean(), 1.0 / std::cos(deg2rad(3.0)), 0.01);
}

TEST(SensorOptionsFile, BadInstallationConfigNamesTheKey) {
  auto expect_error = [](const std::string& yaml, const std::string& key) {
    const Config bad = Config::parse(yaml, "bad_sensors.yaml");
    try {
      SensorOptions::from_config(bad, "s");
      ADD_FAILURE() << "expected a ConfigError for " << key;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad_sensors.yaml"), std::string::npos) << e.what();
    }
  };
  expect_error("s:\n  ins:\n    yaw_gm_sigma_deg: -0.1\n", "s.ins.yaw_gm_sigma_deg");
  expect_error("s:\n  ins:\n    yaw_gm_tau_s: 0\n", "s.ins.yaw_gm_tau_s");
  expect_error("s:\n  ins:\n    roll_pitch_gm_tau_s: 0\n", "s.ins.roll_pitch_gm_tau_s");
  expect_error("s:\n  camera:\n    boresight_deg: [0, 0, 0]\n", "s.camera.boresight_deg");
  expect_error("s:\n  camera:\n    boresight_rpy_deg: [0, 0]\n", "s.camera.boresight_rpy_deg");
  expect_error("s:\n  altimeter:\n    scale: -1\n", "s.altimeter.scale");
  expect_error("s:\n  altimeter:\n    noise_m: -0.1\n", "s.altimeter.noise_m");
  expect_error("s:\n  lidar: {}\n", "s.lidar");
  for (const std::string set : {"standard", "ideal", "correlated_ins", "realistic", "calibration_test"})
    EXPECT_NO_THROW(testing::sensor_set(set)) << set;
}

TEST(SensorOptionsFile, BadValueNamesFileAndKey) {
  const Config bad = Config::parse("standard:\n  ins:\n    yaw_noise_deg: -1\n", "bad_sensors.yaml");
  try {
    SensorOptions::from_config(bad, "standard");
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bad_sensors.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("standard.ins.yaw_noise_deg"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SensorOptions::from_config(bad, "nonexistent"), ConfigError);
}

}  // namespace
}  // namespace nadir::sim
