#include "processes/sim/sensor_options.h"

#include <yaml-cpp/yaml.h>

#include <cmath>

namespace nadir::sim {

SensorOptions SensorOptions::from_config(const Config& root, const std::string& set_name) {
  SensorOptions o;
  o.set_name = set_name;
  o.source = root.source();
  if (!root.has(set_name)) throw root.error(set_name, "is not a sensor set in this file");
  const Config s = root.section(set_name);
  const Config ins = s.section_or_empty("ins");
  o.ins.rate_hz = ins.get<double>("rate_hz", o.ins.rate_hz);
  o.ins.roll_pitch_noise_deg = ins.get<double>("roll_pitch_noise_deg", o.ins.roll_pitch_noise_deg);
  o.ins.yaw_noise_deg = ins.get<double>("yaw_noise_deg", o.ins.yaw_noise_deg);
  o.ins.yaw_bias_initial_deg = ins.get<double>("yaw_bias_initial_deg", o.ins.yaw_bias_initial_deg);
  o.ins.yaw_bias_walk_deg_per_sqrt_s = ins.get<double>("yaw_bias_walk_deg_per_sqrt_s", o.ins.yaw_bias_walk_deg_per_sqrt_s);
  o.ins.roll_pitch_gm_sigma_deg = ins.get<double>("roll_pitch_gm_sigma_deg", o.ins.roll_pitch_gm_sigma_deg);
  o.ins.roll_pitch_gm_tau_s = ins.get<double>("roll_pitch_gm_tau_s", o.ins.roll_pitch_gm_tau_s);
  const Config alt = s.section_or_empty("altimeter");
  o.altimeter.rate_hz = alt.get<double>("rate_hz", o.altimeter.rate_hz);
  o.altimeter.noise_m = alt.get<double>("noise_m", o.altimeter.noise_m);
  o.altimeter.noise_pct = alt.get<double>("noise_pct", o.altimeter.noise_pct);
  o.altimeter.dropout_probability = alt.get<double>("dropout_probability", o.altimeter.dropout_probability);
  o.altimeter.max_range_m = alt.get<double>("max_range_m", o.altimeter.max_range_m);
  const Config cam = s.section_or_empty("camera");
  o.camera.trigger_jitter_us = cam.get<double>("trigger_jitter_us", o.camera.trigger_jitter_us);
  o.camera.frame_drop_probability = cam.get<double>("frame_drop_probability", o.camera.frame_drop_probability);
  o.camera.pixel_noise_dn = cam.get<double>("pixel_noise_dn", o.camera.pixel_noise_dn);
  o.camera.exposure_us = cam.get<double>("exposure_us", o.camera.exposure_us);
  o.camera.gain_db = cam.get<double>("gain_db", o.camera.gain_db);
  // Range errors name the set's file and the dotted key.
  const std::string prefix = set_name + ".";
  const SensorOptions& c = o;
  auto check = [&](bool ok, const std::string& key, const std::string& what) {
    require_option(ok, root.source(), prefix + key, what);
  };
  check(c.ins.rate_hz >= 1 && c.ins.rate_hz <= 1000, "ins.rate_hz", "must be in [1, 1000]");
  check(c.ins.roll_pitch_noise_deg >= 0 && c.ins.roll_pitch_noise_deg <= 10, "ins.roll_pitch_noise_deg", "must be in [0, 10]");
  check(c.ins.yaw_noise_deg >= 0 && c.ins.yaw_noise_deg <= 10, "ins.yaw_noise_deg", "must be in [0, 10]");
  check(std::fabs(c.ins.yaw_bias_initial_deg) <= 30, "ins.yaw_bias_initial_deg", "must be in [-30, 30]");
  check(c.ins.yaw_bias_walk_deg_per_sqrt_s >= 0 && c.ins.yaw_bias_walk_deg_per_sqrt_s <= 1,
        "ins.yaw_bias_walk_deg_per_sqrt_s", "must be in [0, 1]");
  check(c.ins.roll_pitch_gm_sigma_deg >= 0 && c.ins.roll_pitch_gm_sigma_deg <= 10, "ins.roll_pitch_gm_sigma_deg",
        "must be in [0, 10]");
  check(c.ins.roll_pitch_gm_tau_s >= 0.01 && c.ins.roll_pitch_gm_tau_s <= 1e5, "ins.roll_pitch_gm_tau_s",
        "must be in [0.01, 1e5]");
  check(c.altimeter.rate_hz >= 0.1 && c.altimeter.rate_hz <= 1000, "altimeter.rate_hz", "must be in [0.1, 1000]");
  check(c.altimeter.noise_m >= 0 && c.altimeter.noise_m <= 100, "altimeter.noise_m", "must be in [0, 100]");
  check(c.altimeter.noise_pct >= 0 && c.altimeter.noise_pct <= 20, "altimeter.noise_pct", "must be in [0, 20]");
  check(c.altimeter.dropout_probability >= 0 && c.altimeter.dropout_probability <= 1, "altimeter.dropout_probability",
        "must be in [0, 1]");
  check(c.altimeter.max_range_m >= 10 && c.altimeter.max_range_m <= 1e5, "altimeter.max_range_m", "must be in [10, 1e5]");
  check(c.camera.trigger_jitter_us >= 0 && c.camera.trigger_jitter_us <= 5000, "camera.trigger_jitter_us", "must be in [0, 5000]");
  check(c.camera.frame_drop_probability >= 0 && c.camera.frame_drop_probability <= 0.5, "camera.frame_drop_probability",
        "must be in [0, 0.5]");
  check(c.camera.pixel_noise_dn >= 0 && c.camera.pixel_noise_dn <= 50, "camera.pixel_noise_dn", "must be in [0, 50]");
  check(c.camera.exposure_us > 0 && c.camera.exposure_us <= 1e6, "camera.exposure_us", "must be in (0, 1e6]");
  check(c.camera.gain_db >= 0 && c.camera.gain_db <= 48, "camera.gain_db", "must be in [0, 48]");
  return o;
}

void SensorOptions::Check() const {
  const std::string src = source.empty() ? "sensor options" : source;
  require_option(ins.roll_pitch_noise_deg >= 0 && ins.roll_pitch_noise_deg <= 10, src, "ins.roll_pitch_noise_deg",
                 "must be in [0, 10]");
  require_option(ins.yaw_noise_deg >= 0 && ins.yaw_noise_deg <= 10, src, "ins.yaw_noise_deg", "must be in [0, 10]");
  require_option(altimeter.noise_pct >= 0 && altimeter.noise_pct <= 20, src, "altimeter.noise_pct", "must be in [0, 20]");
  require_option(ins.rate_hz >= 1 && ins.rate_hz <= 1000, src, "ins.rate_hz", "must be in [1, 1000]");
  require_option(altimeter.rate_hz >= 0.1 && altimeter.rate_hz <= 1000, src, "altimeter.rate_hz", "must be in [0.1, 1000]");
}

std::string SensorOptions::to_yaml() const {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "set" << YAML::Value << set_name;
  out << YAML::Key << "ins" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rate_hz" << YAML::Value << ins.rate_hz;
  out << YAML::Key << "roll_pitch_noise_deg" << YAML::Value << ins.roll_pitch_noise_deg;
  out << YAML::Key << "yaw_noise_deg" << YAML::Value << ins.yaw_noise_deg;
  out << YAML::Key << "yaw_bias_initial_deg" << YAML::Value << ins.yaw_bias_initial_deg;
  out << YAML::Key << "yaw_bias_walk_deg_per_sqrt_s" << YAML::Value << ins.yaw_bias_walk_deg_per_sqrt_s;
  if (ins.roll_pitch_gm_sigma_deg > 0) {  // only when used: the logged YAML of the existing sets stays as it was
    out << YAML::Key << "roll_pitch_gm_sigma_deg" << YAML::Value << ins.roll_pitch_gm_sigma_deg;
    out << YAML::Key << "roll_pitch_gm_tau_s" << YAML::Value << ins.roll_pitch_gm_tau_s;
  }
  out << YAML::EndMap;
  out << YAML::Key << "altimeter" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rate_hz" << YAML::Value << altimeter.rate_hz;
  out << YAML::Key << "noise_m" << YAML::Value << altimeter.noise_m;
  out << YAML::Key << "noise_pct" << YAML::Value << altimeter.noise_pct;
  out << YAML::Key << "dropout_probability" << YAML::Value << altimeter.dropout_probability;
  out << YAML::Key << "max_range_m" << YAML::Value << altimeter.max_range_m;
  out << YAML::EndMap;
  out << YAML::Key << "camera" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "trigger_jitter_us" << YAML::Value << camera.trigger_jitter_us;
  out << YAML::Key << "frame_drop_probability" << YAML::Value << camera.frame_drop_probability;
  out << YAML::Key << "pixel_noise_dn" << YAML::Value << camera.pixel_noise_dn;
  out << YAML::Key << "exposure_us" << YAML::Value << camera.exposure_us;
  out << YAML::Key << "gain_db" << YAML::Value << camera.gain_db;
  out << YAML::EndMap;
  out << YAML::EndMap;
  return out.c_str();
}

}  // namespace nadir::sim
