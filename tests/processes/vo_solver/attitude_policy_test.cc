// The `propagate` attitude policy against `interpolate` and against the truth
// on noise-free INS data: exact for a constant body rate, bounded in a
// manoeuvre, and never waiting for the INS sample after a frame.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

#include "common/geometry.h"
#include "processes/vo_solver/frame_sync.h"

namespace nadir::vo {
namespace {

constexpr int64_t kInsPeriod = 10000;  // 100 Hz
constexpr int64_t kStart = 1000000;

struct TrueAttitude {
  Eigen::Matrix3d world_from_body;
  Eigen::Vector3d body_rate;
};
using Trajectory = std::function<TrueAttitude(double t_s)>;

ins_t sample(const Trajectory& truth, int64_t utime, bool with_rates) {
  const TrueAttitude a = truth(static_cast<double>(utime - kStart) * 1e-6);
  const Eigen::Vector3d rpy = rpy_from_rotation(a.world_from_body);
  ins_t m{};
  m.utime = utime;
  m.roll = rpy.x();
  m.pitch = rpy.y();
  m.yaw = rpy.z();
  m.has_rates = with_rates;
  for (int i = 0; i < 3; ++i) m.angular_rate[i] = with_rates ? a.body_rate[i] : 0.0;
  return m;
}

double angle_between(const FrameState& s, const Eigen::Matrix3d& r) {
  return Eigen::AngleAxisd(rotation_from_rpy(s.roll, s.pitch, s.yaw).transpose() * r).angle();
}

SyncOptions with_policy(AttitudePolicy policy) {
  SyncOptions options;
  options.attitude_policy = policy;
  return options;
}

// Constant body rate: R(t) = R0 exp([w]x t), written with Eigen's AngleAxis,
// not with the code under test.
TrueAttitude constant_rate(double t_s) {
  const Eigen::Vector3d w(0.05, -0.03, 0.2);
  const Eigen::Matrix3d r0 = rotation_from_rpy(0.1, -0.05, 3.0);
  return {r0 * Eigen::AngleAxisd(w.norm() * t_s, w.normalized()).toRotationMatrix(), w};
}

// A manoeuvre: roll 20 deg at 0.2 Hz (25 deg/s peak rate, 32 deg/s^2), pitch
// 5 deg at 0.3 Hz, yaw 6 deg/s. Body rates from the Euler rates (ZYX).
TrueAttitude manoeuvre(double t_s) {
  const double a_roll = deg_to_rad(20.0), w_roll = 2 * M_PI * 0.2;
  const double a_pitch = deg_to_rad(5.0), w_pitch = 2 * M_PI * 0.3;
  const double yaw_rate = deg_to_rad(6.0);
  const double roll = a_roll * std::sin(w_roll * t_s), roll_dot = a_roll * w_roll * std::cos(w_roll * t_s);
  const double pitch = a_pitch * std::sin(w_pitch * t_s), pitch_dot = a_pitch * w_pitch * std::cos(w_pitch * t_s);
  const double yaw = 1.0 + yaw_rate * t_s;
  const Eigen::Vector3d rate(roll_dot - yaw_rate * std::sin(pitch),
                             pitch_dot * std::cos(roll) + yaw_rate * std::cos(pitch) * std::sin(roll),
                             -pitch_dot * std::sin(roll) + yaw_rate * std::cos(pitch) * std::cos(roll));
  return {rotation_from_rpy(roll, pitch, yaw), rate};
}

// Largest attitude error (rad) over frames at 14 Hz with a 20 us jitter-like
// offset pattern, with the INS samples up to (and including) the first one
// after each frame delivered, as a live run has them.
double worst_error(const Trajectory& truth, AttitudePolicy policy, bool with_rates, double seconds,
                   double* worst_vs_other = nullptr) {
  FrameSync sync(with_policy(policy), Eigen::Vector3d::UnitZ());
  FrameSync other(with_policy(policy == AttitudePolicy::kPropagate ? AttitudePolicy::kInterpolate
                                                                   : AttitudePolicy::kPropagate),
                  Eigen::Vector3d::UnitZ());
  double worst = 0;
  int64_t next_ins = kStart;
  const int frames = static_cast<int>(seconds * 14);
  for (int k = 1; k < frames; ++k) {
    const int64_t frame = kStart + k * 71429 + (k * 37 % 41) * 113;  // off the INS grid, varied phase
    while (next_ins <= frame + kInsPeriod) {
      sync.add_ins(sample(truth, next_ins, with_rates));
      other.add_ins(sample(truth, next_ins, with_rates));
      next_ins += kInsPeriod;
    }
    const FrameState& s = sync.frame_state(frame);
    EXPECT_TRUE(s.has_attitude) << frame;
    worst = std::max(worst, angle_between(s, truth(static_cast<double>(frame - kStart) * 1e-6).world_from_body));
    if (worst_vs_other != nullptr) {
      const FrameState& o = other.frame_state(frame);
      *worst_vs_other = std::max(*worst_vs_other, angle_between(s, rotation_from_rpy(o.roll, o.pitch, o.yaw)));
    }
  }
  return worst;
}

TEST(AttitudePolicy, PolicyNamesRoundTrip) {
  EXPECT_EQ(attitude_policy_from_name("propagate"), AttitudePolicy::kPropagate);
  EXPECT_EQ(attitude_policy_from_name("interpolate"), AttitudePolicy::kInterpolate);
  EXPECT_EQ(attitude_policy_from_name("auto"), AttitudePolicy::kAuto);
  EXPECT_STREQ(attitude_policy_name(AttitudePolicy::kPropagate), "propagate");
  EXPECT_STREQ(attitude_policy_name(AttitudePolicy::kInterpolate), "interpolate");
  EXPECT_STREQ(attitude_policy_name(AttitudePolicy::kAuto), "auto");
  EXPECT_EQ(SyncOptions{}.attitude_policy, AttitudePolicy::kAuto);  // the default
  EXPECT_THROW(attitude_policy_from_name("latest"), std::invalid_argument);
}

TEST(AttitudePolicy, PropagationIsExactForAConstantBodyRate) {
  for (const bool with_rates : {true, false}) {
    SCOPED_TRACE(with_rates ? "INS rates" : "rate from the last two samples");
    EXPECT_LT(worst_error(constant_rate, AttitudePolicy::kPropagate, with_rates, 5.0), 1e-12);
  }
}

TEST(AttitudePolicy, PropagationErrorIsBoundedAgainstInterpolation) {
  // Propagating over dt <= 10 ms with the sample's rate errs by about
  // alpha dt^2 / 2 (alpha = 0.55 rad/s^2 here: 2.8e-5 rad); interpolation by
  // about alpha T^2 / 8 (0.7e-5 rad). From the last two samples instead of
  // rates: about alpha T (T/2 + dt) (8e-5 rad).
  double propagate_vs_interpolate = 0;
  const double propagate = worst_error(manoeuvre, AttitudePolicy::kPropagate, true, 20.0, &propagate_vs_interpolate);
  const double interpolate = worst_error(manoeuvre, AttitudePolicy::kInterpolate, true, 20.0);
  const double from_samples = worst_error(manoeuvre, AttitudePolicy::kPropagate, false, 20.0);
  std::printf("worst attitude error, deg: propagate (rates) %.5f, propagate (two samples) %.5f, interpolate %.5f; "
              "propagate vs interpolate %.5f\n",
              rad_to_deg(propagate), rad_to_deg(from_samples), rad_to_deg(interpolate),
              rad_to_deg(propagate_vs_interpolate));
  EXPECT_LT(propagate, 3.5e-5);
  EXPECT_LT(interpolate, 1.0e-5);
  EXPECT_LT(propagate_vs_interpolate, 4.0e-5);
  EXPECT_LT(from_samples, 1.0e-4);
}

// Roll error rms / sigma of each policy over 4,000 frames at 14 Hz on a
// 100 Hz INS (constant body rate, with or without reported rates) whose roll
// carries white noise of sigma 0.05 deg; `over_share`: the mean of each
// frame's squared error over sigma^2 times its attitude_noise_share instead
// (1 when the share is the frame attitude's noise variance).
std::vector<double> roll_noise_over_sigma(const std::vector<AttitudePolicy>& policies, bool with_rates,
                                          unsigned seed, bool over_share = false) {
  const double sigma = deg_to_rad(0.05);
  std::vector<FrameSync> sync;
  for (AttitudePolicy p : policies) sync.emplace_back(with_policy(p), Eigen::Vector3d::UnitZ());
  std::vector<double> sum_sq(policies.size(), 0.0);
  int frames = 0;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  int64_t next_ins = kStart;
  for (int k = 1; k < 4000; ++k) {
    const int64_t frame = kStart + k * 71429 + (k * 37 % 41) * 113;
    while (next_ins <= frame + kInsPeriod) {
      ins_t m = sample(constant_rate, next_ins, with_rates);
      m.roll += noise(rng);
      for (FrameSync& s : sync) s.add_ins(m);
      next_ins += kInsPeriod;
    }
    const double truth = rpy_from_rotation(constant_rate(static_cast<double>(frame - kStart) * 1e-6).world_from_body).x();
    for (size_t p = 0; p < sync.size(); ++p) {
      const FrameState& s = sync[p].frame_state(frame);
      const double e = angle_difference(s.roll, truth);
      sum_sq[p] += over_share ? e * e / s.attitude_noise_share : e * e;
    }
    ++frames;
  }
  std::vector<double> out;
  for (double v : sum_sq) out.push_back(over_share ? v / frames / (sigma * sigma) : std::sqrt(v / frames) / sigma);
  return out;
}

// White noise on the INS roll (the simulator's INS, sigma 0.05 deg): propagate
// averages the two samples at or before the frame, each carried to it, so the
// noise enters with variance sigma^2 / 2; interpolation weights the samples
// around the frame by (1 - f, f), sigma^2 (1 - 2f + 2f^2), 2/3 sigma^2 on average.
TEST(AttitudePolicy, PropagateAveragesTheInsWhiteNoiseOfTwoSamples) {
  const std::vector<double> rms =
      roll_noise_over_sigma({AttitudePolicy::kPropagate, AttitudePolicy::kInterpolate}, true, 5);
  std::printf("roll error rms / sigma: propagate %.3f (expected 0.707), interpolate %.3f (0.816)\n", rms[0], rms[1]);
  EXPECT_NEAR(rms[0], std::sqrt(0.5), 0.05);
  EXPECT_NEAR(rms[1], std::sqrt(2.0 / 3.0), 0.05);
}

// The share each frame reports (what the uncertainty models scale the INS's
// white noise by) is its attitude's noise variance, frame by frame: averaged
// (propagate with rates), interpolated at each frame's own fraction, and
// carried on past the newest sample by a rate-less INS (more than one
// sample's noise). 4,000 frames: the mean is within 3.5 of its own sigmas of 1.
TEST(AttitudePolicy, AttitudeNoiseShareIsTheFrameAttitudesNoiseVariance) {
  const std::vector<AttitudePolicy> policies = {AttitudePolicy::kPropagate, AttitudePolicy::kInterpolate};
  const std::vector<double> with_rates = roll_noise_over_sigma(policies, true, 7, true);
  const std::vector<double> without_rates = roll_noise_over_sigma(policies, false, 8, true);
  std::printf("squared roll error / (share sigma^2): with rates %.3f %.3f, without %.3f %.3f (expected 1)\n",
              with_rates[0], with_rates[1], without_rates[0], without_rates[1]);
  for (double v : with_rates) EXPECT_NEAR(v, 1.0, 0.08);
  for (double v : without_rates) EXPECT_NEAR(v, 1.0, 0.08);
}

TEST(AttitudePolicy, PropagateSolvesWithoutTheNextInsSample) {
  FrameSync sync(with_policy(AttitudePolicy::kPropagate), Eigen::Vector3d::UnitZ());
  for (int64_t t = kStart; t <= kStart + 50000; t += kInsPeriod) sync.add_ins(sample(manoeuvre, t, true));
  const int64_t newest = kStart + 50000;
  EXPECT_TRUE(sync.ready(newest + 4000));
  EXPECT_TRUE(sync.ready(newest + 8999));
  EXPECT_FALSE(sync.ready(newest + 9000)) << "the next sample (10 ms on) could be at or before this frame";
  const FrameState early = sync.frame_state(newest + 4000);
  sync.add_ins(sample(manoeuvre, newest + kInsPeriod, true));
  EXPECT_TRUE(sync.ready(newest + 9500));

  // The same frame computed with the later sample already there: the same bits.
  FrameSync late(with_policy(AttitudePolicy::kPropagate), Eigen::Vector3d::UnitZ());
  for (int64_t t = kStart; t <= newest + 2 * kInsPeriod; t += kInsPeriod) late.add_ins(sample(manoeuvre, t, true));
  const FrameState& full = late.frame_state(newest + 4000);
  EXPECT_EQ(full.roll, early.roll);
  EXPECT_EQ(full.pitch, early.pitch);
  EXPECT_EQ(full.yaw, early.yaw);
}

TEST(AttitudePolicy, AShortInsIntervalMakesPropagateWaitLonger) {
  FrameSync sync(with_policy(AttitudePolicy::kPropagate), Eigen::Vector3d::UnitZ());
  sync.add_ins(sample(manoeuvre, kStart, true));
  sync.add_ins(sample(manoeuvre, kStart + 5000, true));  // 200 Hz for once
  EXPECT_EQ(sync.short_ins_intervals(), 1);
  EXPECT_TRUE(sync.ready(kStart + 9000));
  EXPECT_FALSE(sync.ready(kStart + 10000)) << "another sample 5 ms on could still be at or before the frame";
}

TEST(AttitudePolicy, SettleTimeMeansWaitingForALaterSample) {
  SyncOptions options = with_policy(AttitudePolicy::kPropagate);
  options.settle_us = 400000;
  FrameSync sync(options, Eigen::Vector3d::UnitZ());
  sync.add_ins(sample(manoeuvre, kStart, true));
  EXPECT_FALSE(sync.ready(kStart + 1000)) << "a reordering channel may still deliver an earlier sample";
  sync.add_ins(sample(manoeuvre, kStart + 401000, true));
  EXPECT_TRUE(sync.ready(kStart + 1000));
}

// auto: the same bits as propagate where the INS reports body rates (and no
// wait for the next sample), the same bits as interpolate where it does not
// (and a wait for the sample after the frame).
TEST(AttitudePolicy, AutoPropagatesWithRatesAndInterpolatesWithout) {
  for (const bool with_rates : {true, false}) {
    SCOPED_TRACE(with_rates ? "INS rates" : "no rates");
    const AttitudePolicy same_as = with_rates ? AttitudePolicy::kPropagate : AttitudePolicy::kInterpolate;
    FrameSync automatic(with_policy(AttitudePolicy::kAuto), Eigen::Vector3d::UnitZ());
    FrameSync reference(with_policy(same_as), Eigen::Vector3d::UnitZ());
    int64_t next_ins = kStart;
    for (int k = 1; k < 200; ++k) {
      const int64_t frame = kStart + k * 71429 + (k * 37 % 41) * 113;
      while (next_ins <= frame) {
        automatic.add_ins(sample(manoeuvre, next_ins, with_rates));
        reference.add_ins(sample(manoeuvre, next_ins, with_rates));
        next_ins += kInsPeriod;
      }
      // Only the samples at or before the frame are in: with rates, the frame
      // goes as soon as the next sample cannot be at or before it (9 ms).
      const int64_t newest = next_ins - kInsPeriod;
      ASSERT_EQ(automatic.ready(frame), with_rates && frame - newest < 9000) << frame;
      automatic.add_ins(sample(manoeuvre, next_ins, with_rates));
      reference.add_ins(sample(manoeuvre, next_ins, with_rates));
      next_ins += kInsPeriod;
      ASSERT_TRUE(automatic.ready(frame));
      const FrameState& a = automatic.frame_state(frame);
      const FrameState& r = reference.frame_state(frame);
      ASSERT_TRUE(a.has_attitude);
      EXPECT_EQ(a.roll, r.roll) << frame;
      EXPECT_EQ(a.pitch, r.pitch) << frame;
      EXPECT_EQ(a.yaw, r.yaw) << frame;
    }
  }
}

// Why auto does not propagate a rate-less INS: carried on with the rate
// between its two newest samples, white attitude noise sigma grows to
// sigma sqrt((1 + r)^2 + r^2) at r = dt / T past the newest sample
// (sqrt(8/3) = 1.63 sigma rms over the phases), where interpolation averages
// it (0.816 sigma).
TEST(AttitudePolicy, WithoutRatesPropagationAmplifiesTheInsNoiseAndAutoDoesNot) {
  const std::vector<double> rms = roll_noise_over_sigma(
      {AttitudePolicy::kPropagate, AttitudePolicy::kInterpolate, AttitudePolicy::kAuto}, false, 7);
  std::printf("rate-less INS, roll error rms / sigma: propagate %.3f (expected 1.633), interpolate %.3f (0.816), "
              "auto %.3f\n", rms[0], rms[1], rms[2]);
  EXPECT_NEAR(rms[0], std::sqrt(8.0 / 3.0), 0.08);
  EXPECT_NEAR(rms[1], std::sqrt(2.0 / 3.0), 0.05);
  EXPECT_EQ(rms[2], rms[1]);
}

}  // namespace
}  // namespace nadir::vo
