#pragma once
// The sensor uncertainty of VO_DELTA that the VO solver puts on each delta and
// yaw fusion takes apart again: the options of `vo_solver.uncertainty:` and
// the per-frame levelling variances both processes compute the same way.

#include "common/config.h"
#include "common/options_schema.h"

namespace nadir {

// Sensor uncertainty of the inputs every solve takes as exact. Defaults: the
// `standard` sensor set of config/sim_sensors.yaml (documented there).
struct DeltaUncertaintyOptions {
  bool enabled = true;                       // false: VO_DELTA carries the image covariance only
  double roll_pitch_stddev_deg = 0.05;       // INS roll/pitch white noise per sample
  // INS roll/pitch error correlated from sample to sample (an aided INS's
  // Gauss-Markov levelling error): unlike the white noise, not reduced where
  // a frame's attitude is made from two samples.
  double roll_pitch_correlated_stddev_deg = 0.0;
  double yaw_stddev_deg = 0.1;               // INS yaw white noise (enters the `flow` variant's dyaw only)
  double altimeter_stddev_m = 0.1;           // range noise, constant part ...
  double altimeter_stddev_fraction = 0.001;  // ... plus this fraction of the range
  double range_scale_stddev = 0.0;           // systematic range scale error (1 sigma, fraction)
  // Model error, independent between deltas: the ground in the footprint is
  // not the one plane through the altimeter spot (relief), so the motion is
  // off by an error that grows like a random walk in the distance flown --
  // sigma = walk * sqrt(metres), along the step and across it -- and each
  // heading change by an angle. The walks were fitted (maximum likelihood,
  // the telescoping levelling part taken out) to the final along- and
  // across-track VO errors of 45 simulated flights, test1-3 (150-300 m,
  // 20-30 m/s, 60 s) x seeds 2401-2408 and 2411-2417: along 0.068, across
  // 0.012 m/sqrt(m). The error varies from terrain to terrain (seeds
  // 2401-2408 alone: 0.051, 2411-2417 alone: 0.083) and somewhat by profile
  // (test1 0.055, test3 0.079); a walk per second of flight fitted them as
  // well, a walk per metre times the height or a fraction of each step (the
  // former relief_scale_stddev, which shrank with the frame rate) worse.
  // Checked on seeds 2421-2427, not used here. README § "Does the reported
  // covariance mean anything?". Describe the terrain flown: rougher ground
  // needs more.
  // These two are the one-plane variants' (paper, level_ground, homography,
  // flow). feature_depth solves each tracked feature's own depth, and its
  // error grows far more slowly: its walks are the feature_depth_walk_*
  // below.
  double relief_walk_along_m_per_sqrt_m = 0.068;
  double relief_walk_across_m_per_sqrt_m = 0.012;
  // The feature_depth variant's model error, a random walk in the distance
  // flown like the above. Fitted to how the VO's own translation error (each
  // pair's error in its own level frame, so without the heading) grows over
  // windows of 0.5-8 km of six whole simulated flights, test1 and test2 x
  // seeds 701-704 / 701-702: the slope of its mean square against the
  // distance, along 0.0060 and 0.0033, across 0.0015 and 0.0010 m/sqrt(m)
  // (studies/consistency/vo_error_growth.py). With paper's 0.068 / 0.012 the
  // reported sigma of a whole Table 1 flight was 3-5x its error. Over rough
  // relief the error grows faster: rough_250 / rough_120 (relief x3, seeds
  // 701-703) pooled 0.012 / 0.025 along, one flight 0.042; across <= 0.004.
  // Describe the terrain flown: rougher ground needs more.
  double feature_depth_walk_along_m_per_sqrt_m = 0.006;
  double feature_depth_walk_across_m_per_sqrt_m = 0.002;
  // ... and the part of it that follows the relief under the aircraft. Each
  // pair's scale comes from the altimeter's spot on a surface fitted to the
  // own depths near it; over relief the ground at the spot departs from that
  // surface by about the own depths' misfit to it (their relative variance
  // beyond their own sigmas, the anchor's model variance), and that error
  // holds while the spot crosses the same ground. Along the step, per metre:
  // model variance x height x this (heights the error holds over). 0: off.
  // Fitted with the walk above on ten whole simulated flights (test1-3,
  // rough_120, rough_250, test2 and test3 over relief x3 / x2.5, a low
  // helicopter; seeds 5001-5012): the windows' mean square along error against the distance
  // their own depths solved and the sum of this term, by least squares, gives
  // the walk 0.0060 m/sqrt(m) again and 0.086, rounded up. On test1-3's relief
  // the own depths hold the surface and the term is zero.
  // (docs/research/2026-12-relief-sigma.md)
  double feature_depth_relief_heights = 0.09;
  double dyaw_model_stddev_deg = 0.005;
  // The heading change chained over many deltas drifts when the INS
  // roll/pitch is noisy: the solver's fit of the ground tilt is biased by the
  // levelling noise on sloping ground, and so is its dyaw, at a rate that
  // follows the slope under the aircraft. Yaw fusion carries it as a
  // first-order Gauss-Markov rate (PoseFilter::apply_heading_drift) with this
  // stddev per degree of roll_pitch_stddev_deg and this correlation time.
  // Fitted to the chained dyaw errors (increments over 0.5-30 s) of simulated
  // flights, test1-3 x 60 s: 0.105 deg/s per deg and 20 s at 0.3 deg noise
  // (42 flights), 0.14 at 0.15 deg (9), 0.09 at 0.05 deg (21); with 0.11 the
  // fused yaw NEES over those flights was 0.76 on average (sigma ~15 % large),
  // with 0.07 0.93, hence 0.07. Checked on flights not used here (README §
  // "Does the reported covariance mean anything?").
  double heading_drift_deg_per_s_per_deg = 0.07;
  double heading_drift_time_s = 20.0;

  // Reads `vo_solver.uncertainty:` (keys as the fields, missing = default).
  static DeltaUncertaintyOptions from_config(const Config& vo_solver_section);
  // Throws std::invalid_argument naming the key and its allowed range.
  void Check() const;
  // Every key of `vo_solver.uncertainty:` (options_schema.h).
  static const OptionsSchema<DeltaUncertaintyOptions>& schema();
  double range_stddev(double range_m) const { return altimeter_stddev_m + altimeter_stddev_fraction * range_m; }
  // Stationary stddev (rad/s) of the heading drift rate; 0 when disabled.
  double heading_drift_stddev_rad_s() const;
  // The roll/pitch error (rad, 1 sigma) of a frame's attitude made from INS
  // samples with `white_noise_share` of one sample's white noise variance
  // (attitude_propagation.h): sqrt(white^2 * share + correlated^2).
  double frame_roll_pitch_stddev_rad(double white_noise_share) const;
};

// Levelling variance (m^2 per horizontal axis) of one frame `height_m` above
// the ground: a roll/pitch error eps moves the footprint by height * eps (the
// solver's response, checked by the tests: d dx / d pitch = h within 1 %).
// sensor_covariance puts exactly prev + curr of these on dx and dy (prev at
// est.altitude_m, curr at altitude_m - dz), so that yaw fusion, which keeps the
// levelling error once per frame rather than once per delta, can take
// exactly that part out again (yaw fusion's delta integration).
double levelling_variance_m2(double height_m, double roll_pitch_stddev_rad);
void frame_levelling_variances(double prev_altitude_m, double dz, double prev_roll_pitch_stddev_rad,
                               double curr_roll_pitch_stddev_rad, double* prev_m2, double* curr_m2);

// Heading variance (rad^2) of one frame's levelled frame: the frame is
// levelled by R(roll, pitch) (ZYX), so a roll error delta turns it about the
// vertical by -sin(pitch) * delta and a pitch error not at all. The solver's
// dyaw responds exactly so, -sin(prev pitch) to prev's roll and
// +sin(curr pitch) to curr's (checked by the tests), which delta_model's grid
// does not reproduce (its ground has no tilt to absorb a tilt error, so it
// turns a pitch error into a heading by the bank's perspective).
// sensor_covariance puts exactly prev + curr of these on dyaw; the error
// telescopes over consecutive deltas like the footprint's, and yaw fusion
// keeps it once per frame (PoseFilter::step_frame_yaw_levelling).
double levelling_yaw_variance_rad2(double pitch_rad, double roll_pitch_stddev_rad);

}  // namespace nadir
