#pragma once
// Options of the yaw fusion process (config section `yaw_fusion:`), each
// documented where it is read. Check() throws ConfigError naming the key.

#include <algorithm>
#include <cstdint>
#include <string>

#include "common/attitude_propagation.h"
#include "common/config.h"
#include "common/options_schema.h"
#include "common/sensor_calibration.h"
#include "common/delta_uncertainty_options.h"
#include "processes/yaw_fusion/protection_level.h"
#include "processes/yaw_fusion/coasting.h"

namespace nadir {

enum class AltitudeMode {
  kVoDz,          // down position = sum of VO dz; the altimeter only gives height_agl_m
  kLevelTerrain,  // also correct down with the altimeter, assuming level terrain (gated)
  kBarometric,    // the altimeter is a height above a fixed datum (take-off): down follows it (gated)
};

struct YawFusionOptions {
  // INS yaw measurement.
  double ins_yaw_stddev_deg = 0.5;       // used when the INS reports no yaw stddev
  double max_ins_yaw_stddev_deg = 10.0;  // INS yaw with a larger reported stddev is not used
  double ins_yaw_gate_sigma = 3.0;       // reject INS yaw whose innovation exceeds this many sigma
  int max_consecutive_yaw_rejections = 20;  // then re-initialise yaw from the INS
  double max_ins_bracket_s = 0.5;        // INS samples further apart are not interpolated between
  // Attitude at frame time: interpolate (wait for the INS sample after the
  // frame), propagate (samples at or before it, rotated on with the rates) or
  // auto (propagate where the INS reports rates, interpolate where not).
  AttitudePolicy attitude_policy = AttitudePolicy::kAuto;
  double ins_min_interval_s = 0.009;     // propagate: INS samples are never closer

  // VO delta use.
  // Numerical floors only (a covariance that is exactly 0): VO_DELTA's
  // covariance carries the image, INS, altimeter and model errors (vo_solver.uncertainty).
  double min_translation_stddev_m = 0.001;  // floor on dx/dy/dz stddev
  double min_dyaw_stddev_deg = 0.0001;      // floor on dyaw stddev
  // TOO_FEW_FEATURES | NO_ALTIMETER | NOT_CONVERGED | NO_ATTITUDE: no translation in those;
  // HEADING_CONTRADICTS: a motion whose rotation the INS contradicts is not a good solve.
  int32_t reject_quality_mask = 1 | 2 | 8 | 16 | 256;
  double max_delta_interval_s = 5.0;     // longer deltas are invalid
  double frame_time_tolerance_s = 0.001; // prev_utime this close to the last frame is continuous

  // Order robustness (sensor time).
  double ins_wait_s = 0.5;        // a delta waits at most this long (sensor time) for INS covering it
  double altimeter_wait_s = 0.5;  // ... and for an altimeter sample covering it (interpolate mode)
  // false ("latest", default): height from ranges at or before the frame, no
  // waiting for the next one (lowest latency); true ("interpolate").
  bool altimeter_interpolate = false;
  int max_pending_deltas = 200;   // beyond, the oldest is processed with what is there
  // Published velocity = displacement over this window of VO positions. Per
  // frame, INS roll/pitch noise moves the position by ~h*sigma (0.26 m at
  // 300 m for 0.05 deg) and cancels over the next frames (paper eq. 21-23),
  // so a single-frame velocity is noisy while a windowed one is not.
  double velocity_window_s = 1.0;
  double max_time_jump_s = 5.0;   // a utime this far ahead of all others is dropped unless the
                                  // next message on its channel confirms the jump

  // Altimeter.
  double max_altimeter_age_s = 0.25;  // altimeter samples further from the frame are not used
  AltitudeMode altitude_mode = AltitudeMode::kVoDz;
  // level_terrain: range noise; barometric: the noise of one barometric
  // height (stddev_m + fraction * height; a barometer's is mostly constant).
  double altimeter_stddev_m = 0.2;          // constant part
  double altimeter_stddev_fraction = 0.005; // proportional part
  // level_terrain: beyond this the terrain is re-anchored; barometric: the
  // sample is not used (the datum never moves).
  double altimeter_gate_sigma = 3.0;
  // barometric: after this many gated samples in a row the down position is
  // reset to the barometric height (VO dz has drifted, the barometer has not).
  int altimeter_max_consecutive_rejections = 3;

  // VO gaps.
  double frame_rate_hz = 14.0;             // camera.rate_hz: gap poses are published at this rate
  double gap_velocity_stddev_mps = 2.0;    // error of the last velocity used to dead-reckon a gap
  double gap_yaw_rate_stddev_dps = 2.0;    // unknown yaw rate during a gap
  double gap_max_propagation_s = 5.0;      // dead-reckon with the last velocity this long, then hold
  double gap_max_duration_s = 30.0;        // stop publishing gap poses after this long without VO

  // Errors shared between deltas (processes/yaw_fusion/README.md § Consistency):
  // the INS levelling and altimeter scale parts of each VO_DELTA covariance,
  // read from `vo_solver.uncertainty:` (the same keys the solver uses).
  DeltaUncertaintyOptions sensor_uncertainty;
  // INS yaw error that the filter cannot average away: a random walk (and an
  // initial offset) under the white noise. Defaults: the `standard` sensor set.
  // With a correlation time the offset is a first-order Gauss-Markov error
  // instead (stationary sigma ins_yaw_bias_stddev_deg, e.g. an aided INS's
  // heading accuracy), beside the walk.
  double ins_yaw_bias_stddev_deg = 0.0;             // at the start (Gauss-Markov: always)
  double ins_yaw_bias_walk_deg_per_sqrt_s = 0.004;  // random walk
  double ins_yaw_bias_correlation_s = 0.0;          // 0: the offset is constant
  // POSE.horizontal_protection_level_m (integrity.h).
  ProtectionLevelOptions protection_level;
  // Coasting over deltas whose translation is not trusted (coast: section; coasting.h).
  CoastOptions coast;
  // Absolute horizontal fixes on MAP_FIX (map_matcher), applied as delayed
  // measurements (yaw_fusion_estimator.h): a fix of the frame at t is applied
  // at the first pose at or after t + map_fix_apply_delay_s (a fixed point in
  // sensor time, so that a replay equals the live run whenever the fix came
  // in time), gated at map_fix_gate_sigma (Mahalanobis distance of its
  // innovation against the pose of that frame and the fix's covariance).
  bool map_fix_enabled = true;
  double map_fix_apply_delay_s = 0.5;
  double map_fix_gate_sigma = 4.0;
  // The map's error common to all its fixes (its georeferencing, the shading
  // of another sun), each horizontal axis: fixes are independent of each
  // other only beyond it. Carried as a consider parameter (yaw_fusion_estimator.h).
  double map_fix_systematic_stddev_m = 0.5;
  // The height too: a fix with the DEM's ground under it (MAP_FIX.ground_*)
  // fixes the down position of its frame at that ground, carried to the
  // altimeter's spot along its slope, less the levelled range there. Its
  // error common to all fixes (the DEM's datum, and the INS height at the
  // first pose that places POSE's frame on the Earth) is the vertical
  // consider parameter.
  bool map_fix_vertical = true;
  double map_fix_systematic_vertical_stddev_m = 1.0;
  // Fixes that keep disagreeing with the pose beyond both covariances (the
  // sum of the last this many fixes' NIS beyond its chi-square 99 %
  // quantile) inflate the pose's covariance by their mean NIS per degree of
  // freedom before the next fix (fix_consistency.h); horizontal and height
  // each on their own. 0: never.
  int map_fix_consistency_window = 10;
  // The horizontal fixes estimate the INS heading bias (ins_yaw_bias_*):
  // the drift it makes across the track between fixes, over the whole path.
  // Every translation is then registered with the heading less that
  // estimate, so the drift stops where the fixes stop (PoseFilter::yaw).
  bool map_fix_estimates_heading_bias = true;

  // camera.time_offset_us (INS and altimeter read at a frame's exposure time,
  // stamp + offset; poses keep the stamp), altimeter.range_scale/range_bias_m
  // (ranges corrected as they arrive): common/sensor_calibration.h.
  SensorCalibration calibration;

  // Reads `yaw_fusion:` (and camera.rate_hz, the calibration keys) from the whole config.
  static YawFusionOptions from_config(const Config& root);
  void Check() const;  // throws ConfigError naming the key and allowed range
  // Every key of `yaw_fusion:` (options_schema.h).
  static const OptionsSchema<YawFusionOptions>& schema();

  int64_t ins_wait_us() const { return static_cast<int64_t>(ins_wait_s * 1e6); }
  int64_t altimeter_wait_us() const { return static_cast<int64_t>(altimeter_wait_s * 1e6); }
  // At least max_delta_interval_s: a frame that long after the last one (a
  // photo survey's next photo) is a plausible step of sensor time, not a jump.
  int64_t max_time_jump_us() const {
    return static_cast<int64_t>(std::max(max_time_jump_s, max_delta_interval_s) * 1e6);
  }
  int64_t frame_period_us() const { return static_cast<int64_t>(1e6 / frame_rate_hz); }
};

std::string altitude_mode_name(AltitudeMode mode);

}  // namespace nadir
