// Yaw fusion on a photo survey: one photo every 7 s, INS samples at the
// photo's attitude 1 ms before and after it (70 s between photos 5 and 6) and
// the altimeter 1 ms before it
// (as nadir_import publishes them), heading changes of 180 and 90 deg between
// photos. The VO dyaw predicts across the wrap, the INS yaw steps pass the
// gate, each translation is registered with the heading of its previous
// photo, and a delta over a pause longer than the camera period replaces the
// gap poses dead-reckoned meanwhile. Options as an importer sets them: the frame rate and the delta interval.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/channels.h"
#include "common/geometry.h"
#include "common/input_checks.h"
#include "processes/yaw_fusion/yaw_fusion_estimator.h"

namespace nadir {
namespace {

constexpr int64_t kStart = 1700000000000000;
constexpr int64_t kPeriod = 7000000;
// Photo k's time: every 7 s, with a 70 s pause (a missed stretch) before photo 6.
int64_t photo_time(int k) { return kStart + k * kPeriod + (k >= 6 ? 63000000 : 0); }

double heading(int k) {
  const double turns[] = {0, 0, M_PI, M_PI, M_PI, M_PI_2, M_PI_2, -M_PI_2, -M_PI_2, -M_PI_2};
  return wrap_angle(deg_to_rad(170.0) + turns[k % 10]);
}

TEST(YawFusionPhotoSurvey, HalfTurnsBetweenPhotosAreFusedAndRegistered) {
  YawFusionOptions options;
  options.frame_rate_hz = 1.0 / 7.0;
  options.max_delta_interval_s = 80.0;
  YawFusionEstimator estimator(options);
  const int photos = 10;
  const Eigen::Vector3d step(13.0, -2.0, 0.5);  // in the level frame of the previous photo
  std::vector<Eigen::Vector3d> truth{Eigen::Vector3d::Zero()};
  std::vector<pose_t> poses;
  auto append = [&](std::vector<pose_t> more) { poses.insert(poses.end(), more.begin(), more.end()); };
  for (int k = 0; k < photos; ++k) {
    const int64_t t = photo_time(k);
    altimeter_t a{};
    a.utime = t - 1000;
    a.range_m = 60.0 - truth.back().z();
    a.beam_body[2] = 1.0;
    a.validity = altimeter_t::VALID_OK;
    append(estimator.add_altimeter(a));
    for (int64_t dt : {-1000, 1000}) {
      ins_t ins{};
      ins.utime = t + dt;
      ins.yaw = heading(k);
      ins.has_stddev = true;
      ins.attitude_stddev[0] = ins.attitude_stddev[1] = ins.attitude_stddev[2] = deg_to_rad(0.5);
      append(estimator.add_ins(ins));
    }
    if (k == 0) continue;
    truth.push_back(truth.back() + rotation_from_rpy(0, 0, heading(k - 1)) * step);
    vo_delta_t d{};
    d.utime = t;
    d.prev_utime = photo_time(k - 1);
    d.dx = step.x();
    d.dy = step.y();
    d.dz = step.z();
    d.dyaw = angle_difference(heading(k), heading(k - 1));
    d.altitude_m = 60.0;
    for (int i = 0; i < 3; ++i) d.covariance[i][i] = 0.01;
    d.covariance[3][3] = 1e-6;
    d.variant = "paper";
    append(estimator.add_vo_delta(d));
  }
  // The last photo's delta waits for INS after it: later sensor time releases it.
  ins_t late{};
  late.utime = photo_time(photos);
  late.yaw = heading(photos - 1);
  append(estimator.add_ins(late));

  const YawFusionCounters& c = estimator.counters();
  EXPECT_EQ(c.vo_deltas_invalid, 0) << c.last_problem;
  EXPECT_EQ(c.ins_yaw_rejected, 0) << c.last_problem;
  EXPECT_EQ(c.vo_deltas_integrated, photos - 1);
  EXPECT_EQ(c.time_jumps_dropped, 0);
  // The 70 s pause: gap poses were dead-reckoned before photo 6's delta came
  // (its INS and altimeter come first); the delta replaced them.
  EXPECT_GT(c.gap_poses, 0);
  EXPECT_EQ(c.gap_poses_superseded, 1);
  int k = 0;
  for (const pose_t& p : poses) {
    if (p.utime != photo_time(k)) continue;  // gap poses between photos, if any
    SCOPED_TRACE("photo " + std::to_string(k));
    EXPECT_EQ(p.flags & pose_t::FLAG_INS_YAW_REJECTED, 0);
    EXPECT_NEAR(angle_difference(p.yaw, heading(k)), 0.0, 1e-9);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(p.position_ned[i], truth[k](i), 1e-9);
    ++k;
  }
  EXPECT_EQ(k, photos);
}

// The default input_checks limits are per-second rates: a half turn between
// photos 1 s or more apart passes them (INS yaw step and VO_DELTA dyaw), so
// no fixed limit stands in the way of a photo stream at up to 1 Hz. The time
// limits (max_ahead_s) are the importer's to raise for its photo interval.
TEST(YawFusionPhotoSurvey, InputChecksAdmitAHalfTurnBetweenPhotos) {
  InputCheckOptions checks;
  checks.max_ahead_s = checks.max_behind_s = 30.0;
  InputGate gate(checks);
  const int64_t period = 1000000;
  for (int k = 0; k < 4; ++k) {
    const int64_t t = kStart + k * period;
    for (int64_t dt : {-1000, 1000}) {
      ins_t ins{};
      ins.utime = t + dt;
      ins.yaw = wrap_angle(k * M_PI);
      EXPECT_TRUE(gate.admit(channels::kIns, ins)) << "photo " << k;
    }
    vo_delta_t d{};
    d.utime = t;
    d.prev_utime = k == 0 ? 0 : t - period;
    d.dx = 15.0;
    d.dyaw = k == 0 ? 0.0 : M_PI;
    EXPECT_TRUE(gate.admit(channels::kVoDelta, d)) << "photo " << k;
  }
  EXPECT_EQ(gate.rejected(), 0);
}

}  // namespace
}  // namespace nadir
