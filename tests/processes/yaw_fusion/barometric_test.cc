// altitude_mode: barometric on synthetic flights: the altimeter is a height
// above the take-off point (what a photo survey's RelativeAltitude is), so the
// down position follows it whatever the VO dz says, a spike is gated without
// moving the datum, and a long disagreement resets down to the barometer.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "common/config.h"
#include "processes/yaw_fusion/yaw_fusion_estimator.h"
#include "estimator_runner.h"
#include "synthetic_flight.h"

namespace nadir {
namespace {

using test::FlightSpec;
using test::SyntheticFlight;
using test::run_flight;

constexpr double kBaroStddevM = 0.3;  // as nadir_import sets it for barometric flights

YawFusionOptions barometric_options() {
  YawFusionOptions o;
  o.altitude_mode = AltitudeMode::kBarometric;
  o.altimeter_stddev_m = kBaroStddevM;
  o.altimeter_stddev_fraction = 0.0;
  return o;
}

// The down error of the last pose against the truth (both from the first frame).
double final_down_error(const SyntheticFlight& flight, const std::vector<pose_t>& poses) {
  const double truth = flight.truth.back().position.z() - flight.truth.front().position.z();
  return poses.back().position_ned[2] - truth;
}

// Steady-state lag of a Kalman filter on a random walk (process variance q per
// step, measurement variance r, one measurement per step) behind a state that
// moves by b per step more than the prediction says: the predicted variance p
// solves p^2 - q p - q r = 0, the gain is k = p / (p + r), and the error e
// after an update satisfies e = (1 - k)(e + b), so e = b (1 - k) / k.
double steady_state_lag(double b, double q, double r) {
  const double p = 0.5 * (q + std::sqrt(q * q + 4.0 * q * r));
  const double k = p / (p + r);
  return std::abs(b) * (1.0 - k) / k;
}

TEST(YawFusionBarometric, DownFollowsTheBarometerDespiteABiasedDz) {
  // Climbing 1 m/s over level ground from the take-off height, dz biased by
  // 2 cm per frame (14 m of false descent summed over 700 frames, 60 m over 3000).
  for (int frames : {700, 3000}) {
    FlightSpec spec;
    spec.frames = frames;
    spec.dz_bias_m = 0.02;
    const SyntheticFlight flight = test::make_flight(spec);

    const auto vo_only = run_flight(flight, YawFusionOptions{});
    YawFusionCounters counters;
    const auto baro = run_flight(flight, barometric_options(), &counters);
    const double vo_error = final_down_error(flight, vo_only);
    const double baro_error = final_down_error(flight, baro);
    // The bound: one barometric update per frame, the reported dz stddev as
    // the process noise, the bias as the unmodelled motion: down lags by
    // `lag`. The datum (terrain state) is estimated beside down; it is known
    // only through the chain of dz from the origin, so while down's variance
    // is still small (the first ~1/K frames) the datum takes a share of the
    // same innovations, at most another lag, and then stops moving (measured:
    // 0.21 m at 300, 700, 1500, 3000 and 6000 frames). Bound: 3 lags.
    const double q = spec.covariance_translation_stddev_m * spec.covariance_translation_stddev_m;
    const double lag = steady_state_lag(spec.dz_bias_m, q, kBaroStddevM * kBaroStddevM);
    std::printf("down error after %d frames: vo_dz %.2f m, barometric %.3f m (steady-state lag %.3f m)\n",
                spec.frames, vo_error, baro_error, lag);
    EXPECT_GT(std::abs(vo_error), 0.019 * frames);
    EXPECT_LT(std::abs(baro_error), 3.0 * lag) << frames << " frames";
    EXPECT_EQ(counters.altimeter_rejected, 0);
    EXPECT_EQ(counters.altimeter_down_resets, 0);
    // The published height is still the altimeter's (here the height above take-off).
    EXPECT_NEAR(baro.back().height_agl_m, vo_only.back().height_agl_m, 1e-9);
  }
}

TEST(YawFusionBarometric, SpikesAreGatedAndCountedWithoutMovingDown) {
  FlightSpec spec;
  spec.frames = 700;
  spec.dz_bias_m = 0.02;
  SyntheticFlight flight = test::make_flight(spec);
  const auto clean = run_flight(flight, barometric_options());
  // Three spikes of 25 m, each two altimeter samples (100 ms) long: at most
  // two frames take each one, fewer than altimeter_max_consecutive_rejections.
  for (size_t first : {200u, 400u, 600u}) {
    flight.altimeter[first].range_m += 25.0;
    flight.altimeter[first + 1].range_m += 25.0;
  }
  YawFusionCounters counters;
  const auto spiked = run_flight(flight, barometric_options(), &counters);
  std::printf("spikes: %lld samples rejected, %lld resets, final down %.3f m (without spikes %.3f m)\n",
              static_cast<long long>(counters.altimeter_rejected),
              static_cast<long long>(counters.altimeter_down_resets), spiked.back().position_ned[2],
              clean.back().position_ned[2]);
  EXPECT_GE(counters.altimeter_rejected, 3);  // at least one frame per spike
  EXPECT_LE(counters.altimeter_rejected, 6);
  EXPECT_EQ(counters.altimeter_down_resets, 0);
  // Missing a few updates costs a few frames of lag, not 25 m.
  EXPECT_NEAR(spiked.back().position_ned[2], clean.back().position_ned[2], 0.1);
  ASSERT_EQ(spiked.size(), clean.size());
  for (size_t k = 0; k < spiked.size(); ++k) {
    EXPECT_NEAR(spiked[k].position_ned[2], clean[k].position_ned[2], 0.3) << "pose " << k;
  }
}

TEST(YawFusionBarometric, ALongDisagreementResetsDownToTheBarometer) {
  FlightSpec spec;
  spec.frames = 700;
  SyntheticFlight flight = test::make_flight(spec);
  // One delta's dz wrong by 20 m (a solver glitch the reported 5 cm does not
  // cover). Coasting is off so that the delta is integrated (its vertical gate
  // would coast over it): then every barometric sample disagrees with down.
  flight.deltas[300].dz += 20.0;
  YawFusionOptions options = barometric_options();
  options.coast.enabled = false;
  YawFusionCounters counters;
  const auto baro = run_flight(flight, options, &counters);
  YawFusionOptions vo_dz;
  vo_dz.coast.enabled = false;
  const auto vo_only = run_flight(flight, vo_dz);
  std::printf("20 m dz glitch: vo_dz final down error %.2f m, barometric %.3f m; %lld rejected, %lld resets\n",
              final_down_error(flight, vo_only), final_down_error(flight, baro),
              static_cast<long long>(counters.altimeter_rejected),
              static_cast<long long>(counters.altimeter_down_resets));
  EXPECT_NEAR(final_down_error(flight, vo_only), 20.0, 0.1);
  EXPECT_EQ(counters.altimeter_rejected, options.altimeter_max_consecutive_rejections);
  EXPECT_EQ(counters.altimeter_down_resets, 1);
  // After the reset the barometer is the down (within its noise and the datum's).
  EXPECT_LT(std::abs(final_down_error(flight, baro)), 3.0 * kBaroStddevM);
  // The frames between the glitch and the reset carried it; none after.
  std::map<int64_t, double> truth_down;
  for (const auto& f : flight.truth) truth_down[f.utime] = f.position.z() - flight.truth.front().position.z();
  const int64_t reset_by = flight.truth[310].utime;
  int checked = 0, off = 0;
  for (const pose_t& pose : baro) {
    const auto truth = truth_down.find(pose.utime);
    if (pose.utime < reset_by || truth == truth_down.end()) continue;
    ++checked;
    if (std::abs(pose.position_ned[2] - truth->second) > 1.0) ++off;
  }
  EXPECT_GT(checked, 350);
  EXPECT_EQ(off, 0);
}

TEST(YawFusionBarometric, ModeAndRejectionLimitAreConfigKeys) {
  const Config ok = Config::parse(
      "yaw_fusion: {altitude_mode: barometric, altimeter_stddev_m: 0.3, altimeter_max_consecutive_rejections: 5}\n",
      "test.yaml");
  const YawFusionOptions o = YawFusionOptions::from_config(ok);
  EXPECT_EQ(o.altitude_mode, AltitudeMode::kBarometric);
  EXPECT_EQ(altitude_mode_name(o.altitude_mode), "barometric");
  EXPECT_EQ(o.altimeter_max_consecutive_rejections, 5);
  const Config bad = Config::parse("yaw_fusion: {altimeter_max_consecutive_rejections: 0}\n", "test.yaml");
  try {
    YawFusionOptions::from_config(bad);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("yaw_fusion.altimeter_max_consecutive_rejections"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace nadir
