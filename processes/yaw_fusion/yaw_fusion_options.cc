#include "processes/yaw_fusion/yaw_fusion_options.h"

#include <stdexcept>

namespace nadir {

std::string altitude_mode_name(AltitudeMode mode) {
  switch (mode) {
    case AltitudeMode::kVoDz:
      return "vo_dz";
    case AltitudeMode::kLevelTerrain:
      return "level_terrain";
    case AltitudeMode::kBarometric:
      return "barometric";
  }
  return "unknown";
}

const OptionsSchema<YawFusionOptions>& YawFusionOptions::schema() {
  using O = YawFusionOptions;
  using P = ProtectionLevelOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("yaw_fusion", "Kalman filter on yaw (VO dyaw predicts, INS yaw updates) that registers "
                                     "each VO translation in the world frame and publishes POSE.");
    s.number("ins_yaw_stddev_deg", 1e-4, 30.0, "deg", "used when the INS reports no yaw stddev",
             &O::ins_yaw_stddev_deg)
        .number("max_ins_yaw_stddev_deg", 1e-3, 180.0, "deg", "INS yaw with a larger reported stddev is not used",
                &O::max_ins_yaw_stddev_deg)
        .number("ins_yaw_gate_sigma", 1.0, 100.0, "", "reject INS yaw whose innovation exceeds this many sigma",
                &O::ins_yaw_gate_sigma)
        .number("max_consecutive_yaw_rejections", 1, 100000, "", "then re-initialise yaw from the INS",
                &O::max_consecutive_yaw_rejections)
        .number("max_ins_bracket_s", 0.001, 10.0, "s", "INS samples further apart are not interpolated between",
                &O::max_ins_bracket_s)
        .choice<AttitudePolicy>("attitude_policy",
                                {{"auto", AttitudePolicy::kAuto},
                                 {"interpolate", AttitudePolicy::kInterpolate},
                                 {"propagate", AttitudePolicy::kPropagate}},
                                "INS at a frame: as vo_solver.sync.attitude_policy (auto: propagated where the INS reports rates)", &O::attitude_policy)
        .scaled("ins_min_interval_ms", 1e-3, 0.0, 1000.0, "ms", "propagate: INS samples are never closer",
                &O::ins_min_interval_s)
        .number("min_translation_stddev_m", 0.0, 100.0, "m", "floor on the dx/dy/dz stddev",
                &O::min_translation_stddev_m)
        .number("min_dyaw_stddev_deg", 0.0, 30.0, "deg", "floor on the dyaw stddev", &O::min_dyaw_stddev_deg)
        .number("reject_quality_mask", 0, 0x7fffffff, "bits", "VO_DELTA quality bits that reject a delta",
                &O::reject_quality_mask)
        .number("max_delta_interval_s", 0.001, 600.0, "s", "longer deltas are invalid", &O::max_delta_interval_s)
        .number("frame_time_tolerance_s", 0.0, 0.05, "s", "prev_utime this close to the last frame is continuous",
                &O::frame_time_tolerance_s)
        .number("ins_wait_s", 0.0, 30.0, "s", "a delta waits at most this long (sensor time) for INS covering it",
                &O::ins_wait_s)
        .number("altimeter_wait_s", 0.0, 30.0, "s", "... and for an altimeter sample covering it (interpolate)",
                &O::altimeter_wait_s)
        .choice<bool>("altimeter_mode", {{"latest", false}, {"interpolate", true}},
                      "altimeter range at the frame: the latest sample or interpolated", &O::altimeter_interpolate)
        .number("max_pending_deltas", 1, 100000, "", "beyond, the oldest is processed with what is there",
                &O::max_pending_deltas)
        .number("velocity_window_s", 0.0, 10.0, "s", "window of the published velocity", &O::velocity_window_s)
        .number("max_time_jump_s", 0.1, 1e6, "s", "a utime this far ahead of all others is dropped",
                &O::max_time_jump_s)
        .number("max_altimeter_age_s", 0.001, 10.0, "s", "altimeter samples further from the frame are not used",
                &O::max_altimeter_age_s)
        .choice<AltitudeMode>("altitude_mode",
                              {{"vo_dz", AltitudeMode::kVoDz},
                               {"level_terrain", AltitudeMode::kLevelTerrain},
                               {"barometric", AltitudeMode::kBarometric}},
                              "down from the sum of VO dz, also corrected by the altimeter over level terrain, or "
                              "following a barometric height above take-off",
                              &O::altitude_mode)
        .number("altimeter_stddev_m", 1e-4, 100.0, "m",
                "level_terrain: range noise, constant part; barometric: barometric height noise, constant part",
                &O::altimeter_stddev_m)
        .number("altimeter_stddev_fraction", 0.0, 0.5, "",
                "level_terrain / barometric: the noise's part proportional to the height",
                &O::altimeter_stddev_fraction)
        .number("altimeter_gate_sigma", 1.0, 100.0, "",
                "level_terrain: beyond this the terrain is re-anchored; barometric: the sample is not used",
                &O::altimeter_gate_sigma)
        .number("altimeter_max_consecutive_rejections", 1, 100000, "",
                "barometric: after this many gated samples in a row down is reset to the barometric height",
                &O::altimeter_max_consecutive_rejections)
        .number("gap.velocity_stddev_mps", 0.0, 100.0, "m/s", "error of the last velocity used to dead-reckon a gap",
                &O::gap_velocity_stddev_mps)
        .number("gap.yaw_rate_stddev_dps", 0.0, 180.0, "deg/s", "unknown yaw rate during a gap",
                &O::gap_yaw_rate_stddev_dps)
        .number("gap.max_propagation_s", 0.0, 3600.0, "s", "dead-reckon with the last velocity this long, then hold",
                &O::gap_max_propagation_s)
        .number("gap.max_duration_s", 0.0, 36000.0, "s", "stop publishing gap poses after this long without VO",
                &O::gap_max_duration_s)
        .number("ins_yaw_bias_stddev_deg", 0.0, 30.0, "deg", "INS yaw bias at the start", &O::ins_yaw_bias_stddev_deg)
        .number("ins_yaw_bias_walk_deg_per_sqrt_s", 0.0, 10.0, "deg/sqrt(s)", "INS yaw bias random walk",
                &O::ins_yaw_bias_walk_deg_per_sqrt_s)
        .number("ins_yaw_bias_correlation_s", 0.0, 1e6, "s",
                "correlation time of the INS yaw bias at the start (first-order Gauss-Markov; 0: constant)",
                &O::ins_yaw_bias_correlation_s)
        .number("protection_level.probability", 0.5, 1.0 - 1e-12, "",
                "probability the horizontal protection level bounds the error", &O::protection_level,
                &P::probability)
        .number("protection_level.flagged_inflation", 1.0, 1000.0, "", "protection level factor on flagged poses",
                &O::protection_level, &P::flagged_inflation)
        .include("coast", CoastOptions::schema(), &O::coast)
        .flag("map_fix.enabled", "use MAP_FIX fixes from the map matcher when they come", &O::map_fix_enabled)
        .number("map_fix.apply_delay_s", 0.0, 10.0, "s",
                "a fix of the frame at t is applied at the first pose at or after t + this (sensor time)",
                &O::map_fix_apply_delay_s)
        .number("map_fix.gate_sigma", 1.0, 100.0, "",
                "reject a fix whose innovation exceeds this Mahalanobis distance", &O::map_fix_gate_sigma)
        .number("map_fix.systematic_stddev_m", 0.0, 100.0, "m",
                "the map's error common to all its fixes, each axis: carried, never averaged away by many fixes",
                &O::map_fix_systematic_stddev_m)
        .flag("map_fix.vertical",
              "a fix with the DEM's ground under it fixes the height too (that ground at the altimeter's spot less "
              "the levelled range)",
              &O::map_fix_vertical)
        .number("map_fix.systematic_vertical_stddev_m", 0.0, 100.0, "m",
                "the error common to all fixes' heights: the DEM's datum and the INS height at the first pose "
                "(a consider parameter)",
                &O::map_fix_systematic_vertical_stddev_m)
        .number("map_fix.consistency_window", 0, 1000, "fixes",
                "when the last this many fixes disagree with the pose beyond the chi-square 99 % bound of their "
                "summed NIS, the pose's covariance is inflated by their mean NIS per axis before the next fix "
                "(0: never)",
                &O::map_fix_consistency_window)
        .flag("map_fix.estimates_heading_bias",
              "the horizontal fixes estimate the INS heading bias (from the drift it makes across the track), and "
              "the heading less that estimate registers every step",
              &O::map_fix_estimates_heading_bias)
        .rule("frame_time_tolerance_s", [](const O& o) { return o.frame_time_tolerance_s < 0.5 / o.frame_rate_hz; },
              "must be below half a frame period (camera.rate_hz)")
        .rule("max_time_jump_s",
              [](const O& o) { return o.max_time_jump_s > o.ins_wait_s && o.max_time_jump_s > o.altimeter_wait_s; },
              "must be larger than ins_wait_s and altimeter_wait_s");
    return s;
  }();
  return schema;
}

YawFusionOptions YawFusionOptions::from_config(const Config& root) {
  YawFusionOptions o;
  const Config camera = root.section_or_empty("camera");
  o.frame_rate_hz = camera.get_in_range("rate_hz", o.frame_rate_hz, 0.1, 1000.0);
  o.sensor_uncertainty = DeltaUncertaintyOptions::from_config(root.section_or_empty("vo_solver"));
  o.calibration = SensorCalibration::from_config(root);
  schema().read(root.section_or_empty("yaw_fusion"), &o);
  return o;
}

void YawFusionOptions::Check() const {
  if (!(frame_rate_hz >= 0.1 && frame_rate_hz <= 1000.0)) {
    throw ConfigError("options: key 'camera.rate_hz' must be in [0.1, 1000]");
  }
  schema().check(*this);
  sensor_uncertainty.Check();
  calibration.Check();
}

}  // namespace nadir
