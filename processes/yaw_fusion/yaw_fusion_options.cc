#include "processes/yaw_fusion/yaw_fusion_options.h"

#include <stdexcept>

namespace nadir {

namespace {
// Keys are named with their full dotted path; camera.rate_hz is shared.
void check(bool ok, const std::string& key, const std::string& what) {
  const std::string path = key.rfind("camera.", 0) == 0 ? key : "yaw_fusion." + key;
  require_option(ok, "config", path, what);
}
}  // namespace

std::string altitude_mode_name(AltitudeMode mode) {
  return mode == AltitudeMode::kVoDz ? "vo_dz" : "level_terrain";
}

YawFusionOptions YawFusionOptions::from_config(const Config& root) {
  YawFusionOptions o;
  o.frame_rate_hz = root.section_or_empty("camera").get<double>("rate_hz", o.frame_rate_hz);
  const Config c = root.section_or_empty("yaw_fusion");
  o.ins_yaw_stddev_deg = c.get_in_range("ins_yaw_stddev_deg", o.ins_yaw_stddev_deg, 1e-4, 30.0);
  o.max_ins_yaw_stddev_deg = c.get_in_range("max_ins_yaw_stddev_deg", o.max_ins_yaw_stddev_deg, 1e-3, 180.0);
  o.ins_yaw_gate_sigma = c.get_in_range("ins_yaw_gate_sigma", o.ins_yaw_gate_sigma, 1.0, 100.0);
  o.max_consecutive_yaw_rejections =
      c.get_in_range("max_consecutive_yaw_rejections", o.max_consecutive_yaw_rejections, 1, 100000);
  o.max_ins_bracket_s = c.get_in_range("max_ins_bracket_s", o.max_ins_bracket_s, 0.001, 10.0);
  const std::string attitude_policy = c.get<std::string>("attitude_policy", "interpolate");
  try {
    o.attitude_policy = attitude_policy_from_name(attitude_policy);
  } catch (const std::invalid_argument&) {
    throw c.error("attitude_policy", "= '" + attitude_policy + "' must be propagate or interpolate");
  }
  o.ins_min_interval_s = c.get_in_range("ins_min_interval_ms", o.ins_min_interval_s * 1e3, 0.0, 1000.0) * 1e-3;
  o.min_translation_stddev_m = c.get_in_range("min_translation_stddev_m", o.min_translation_stddev_m, 0.0, 100.0);
  o.min_dyaw_stddev_deg = c.get_in_range("min_dyaw_stddev_deg", o.min_dyaw_stddev_deg, 0.0, 30.0);
  o.reject_quality_mask = c.get_in_range("reject_quality_mask", o.reject_quality_mask, 0, 0x7fffffff);
  o.max_delta_interval_s = c.get_in_range("max_delta_interval_s", o.max_delta_interval_s, 0.001, 600.0);
  o.frame_time_tolerance_s = c.get_in_range("frame_time_tolerance_s", o.frame_time_tolerance_s, 0.0, 0.05);
  o.ins_wait_s = c.get_in_range("ins_wait_s", o.ins_wait_s, 0.0, 30.0);
  o.altimeter_wait_s = c.get_in_range("altimeter_wait_s", o.altimeter_wait_s, 0.0, 30.0);
  const std::string altimeter_mode = c.get<std::string>("altimeter_mode", "latest");
  if (altimeter_mode != "latest" && altimeter_mode != "interpolate") {
    throw c.error("altimeter_mode", "= '" + altimeter_mode + "' must be latest or interpolate");
  }
  o.altimeter_interpolate = altimeter_mode == "interpolate";
  o.max_pending_deltas = c.get_in_range("max_pending_deltas", o.max_pending_deltas, 1, 100000);
  o.velocity_window_s = c.get_in_range("velocity_window_s", o.velocity_window_s, 0.0, 10.0);
  o.max_time_jump_s = c.get_in_range("max_time_jump_s", o.max_time_jump_s, 0.1, 1e6);
  o.max_altimeter_age_s = c.get_in_range("max_altimeter_age_s", o.max_altimeter_age_s, 0.001, 10.0);
  const std::string mode = c.get<std::string>("altitude_mode", altitude_mode_name(o.altitude_mode));
  if (mode == "vo_dz") {
    o.altitude_mode = AltitudeMode::kVoDz;
  } else if (mode == "level_terrain") {
    o.altitude_mode = AltitudeMode::kLevelTerrain;
  } else {
    throw c.error("altitude_mode", "= '" + mode + "' must be one of: vo_dz, level_terrain");
  }
  o.altimeter_stddev_m = c.get_in_range("altimeter_stddev_m", o.altimeter_stddev_m, 1e-4, 100.0);
  o.altimeter_stddev_fraction = c.get_in_range("altimeter_stddev_fraction", o.altimeter_stddev_fraction, 0.0, 0.5);
  o.altimeter_gate_sigma = c.get_in_range("altimeter_gate_sigma", o.altimeter_gate_sigma, 1.0, 100.0);
  const Config gap = c.section_or_empty("gap");
  o.gap_velocity_stddev_mps = gap.get_in_range("velocity_stddev_mps", o.gap_velocity_stddev_mps, 0.0, 100.0);
  o.gap_yaw_rate_stddev_dps = gap.get_in_range("yaw_rate_stddev_dps", o.gap_yaw_rate_stddev_dps, 0.0, 180.0);
  o.gap_max_propagation_s = gap.get_in_range("max_propagation_s", o.gap_max_propagation_s, 0.0, 3600.0);
  o.gap_max_duration_s = gap.get_in_range("max_duration_s", o.gap_max_duration_s, 0.0, 36000.0);
  o.ins_yaw_bias_stddev_deg = c.get_in_range("ins_yaw_bias_stddev_deg", o.ins_yaw_bias_stddev_deg, 0.0, 30.0);
  o.ins_yaw_bias_walk_deg_per_sqrt_s =
      c.get_in_range("ins_yaw_bias_walk_deg_per_sqrt_s", o.ins_yaw_bias_walk_deg_per_sqrt_s, 0.0, 10.0);
  const Config pl = c.section_or_empty("protection_level");
  o.protection_level.probability = pl.get_in_range("probability", o.protection_level.probability, 0.5, 1.0 - 1e-12);
  o.protection_level.flagged_inflation =
      pl.get_in_range("flagged_inflation", o.protection_level.flagged_inflation, 1.0, 1000.0);
  o.sensor_uncertainty = DeltaUncertaintyOptions::from_config(root.section_or_empty("vo_solver"));
  o.coast = CoastOptions::from_config(c.section_or_empty("coast"));
  o.calibration = SensorCalibration::from_config(root);
  o.Check();
  return o;
}

void YawFusionOptions::Check() const {
  check(frame_rate_hz >= 0.1 && frame_rate_hz <= 1000.0, "camera.rate_hz", "must be in [0.1, 1000]");
  check(ins_yaw_stddev_deg > 0.0 && ins_yaw_stddev_deg <= 30.0, "ins_yaw_stddev_deg", "must be in (0, 30]");
  check(max_ins_yaw_stddev_deg > 0.0, "max_ins_yaw_stddev_deg", "must be > 0");
  check(ins_yaw_gate_sigma >= 1.0, "ins_yaw_gate_sigma", "must be >= 1");
  check(max_consecutive_yaw_rejections >= 1, "max_consecutive_yaw_rejections", "must be >= 1");
  check(max_ins_bracket_s > 0.0, "max_ins_bracket_s", "must be > 0");
  check(min_translation_stddev_m >= 0.0, "min_translation_stddev_m", "must be >= 0");
  check(min_dyaw_stddev_deg >= 0.0, "min_dyaw_stddev_deg", "must be >= 0");
  check(reject_quality_mask >= 0, "reject_quality_mask", "must be >= 0");
  check(max_delta_interval_s > 0.0, "max_delta_interval_s", "must be > 0");
  check(frame_time_tolerance_s >= 0.0 && frame_time_tolerance_s < 0.5 / frame_rate_hz, "frame_time_tolerance_s",
        "must be in [0, half a frame period)");
  check(ins_wait_s >= 0.0 && altimeter_wait_s >= 0.0, "ins_wait_s", "waits must be >= 0");
  check(max_pending_deltas >= 1, "max_pending_deltas", "must be >= 1");
  check(max_time_jump_s > ins_wait_s && max_time_jump_s > altimeter_wait_s, "max_time_jump_s",
        "must be larger than ins_wait_s and altimeter_wait_s");
  check(max_altimeter_age_s > 0.0, "max_altimeter_age_s", "must be > 0");
  check(altimeter_stddev_m > 0.0, "altimeter_stddev_m", "must be > 0");
  check(altimeter_gate_sigma >= 1.0, "altimeter_gate_sigma", "must be >= 1");
  check(gap_velocity_stddev_mps >= 0.0, "gap.velocity_stddev_mps", "must be >= 0");
  check(gap_yaw_rate_stddev_dps >= 0.0, "gap.yaw_rate_stddev_dps", "must be >= 0");
  check(gap_max_propagation_s >= 0.0, "gap.max_propagation_s", "must be >= 0");
  check(gap_max_duration_s >= 0.0, "gap.max_duration_s", "must be >= 0");
  check(ins_yaw_bias_stddev_deg >= 0.0, "ins_yaw_bias_stddev_deg", "must be >= 0");
  check(ins_yaw_bias_walk_deg_per_sqrt_s >= 0.0, "ins_yaw_bias_walk_deg_per_sqrt_s", "must be >= 0");
  check(protection_level.probability >= 0.5 && protection_level.probability < 1.0, "protection_level.probability",
        "must be in [0.5, 1)");
  check(protection_level.flagged_inflation >= 1.0, "protection_level.flagged_inflation", "must be >= 1");
  sensor_uncertainty.Check();
  coast.Check();
  calibration.Check();
}

}  // namespace nadir
