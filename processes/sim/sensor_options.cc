#include "processes/sim/sensor_options.h"

#include <yaml-cpp/yaml.h>

#include <cmath>

namespace nadir::sim {
namespace {

// Reads a fixed-length list of numbers, or keeps the fallback when absent.
template <size_t N>
std::array<double, N> get_list(const Config& c, const std::string& key, const std::array<double, N>& fallback) {
  if (!c.has(key)) return fallback;
  const auto v = c.get<std::vector<double>>(key);
  if (v.size() != N) throw c.error(key, "must list " + std::to_string(N) + " numbers");
  std::array<double, N> out{};
  for (size_t i = 0; i < N; ++i) out[i] = v[i];
  return out;
}

template <size_t N>
bool all_within(const std::array<double, N>& v, double limit) {
  for (double x : v)
    if (!(std::fabs(x) <= limit)) return false;
  return true;
}

template <size_t N>
bool any_nonzero(const std::array<double, N>& v) {
  for (double x : v)
    if (x != 0.0) return true;
  return false;
}

template <size_t N>
void emit_list(YAML::Emitter& out, const char* key, const std::array<double, N>& v) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (double x : v) out << x;
  out << YAML::EndSeq;
}

}  // namespace

SensorOptions SensorOptions::from_config(const Config& root, const std::string& set_name) {
  SensorOptions o;
  o.set_name = set_name;
  o.source = root.source();
  if (!root.has(set_name)) throw root.error(set_name, "is not a sensor set in this file");
  const Config s = root.section(set_name);
  s.require_known_keys({"ins", "altimeter", "camera"});
  const Config ins = s.section_or_empty("ins");
  ins.require_known_keys({"rate_hz", "roll_pitch_noise_deg", "yaw_noise_deg", "yaw_bias_initial_deg",
                          "yaw_bias_walk_deg_per_sqrt_s", "roll_pitch_gm_sigma_deg", "roll_pitch_gm_tau_s",
                          "yaw_gm_sigma_deg", "yaw_gm_tau_s"});
  o.ins.rate_hz = ins.get<double>("rate_hz", o.ins.rate_hz);
  o.ins.roll_pitch_noise_deg = ins.get<double>("roll_pitch_noise_deg", o.ins.roll_pitch_noise_deg);
  o.ins.yaw_noise_deg = ins.get<double>("yaw_noise_deg", o.ins.yaw_noise_deg);
  o.ins.yaw_bias_initial_deg = ins.get<double>("yaw_bias_initial_deg", o.ins.yaw_bias_initial_deg);
  o.ins.yaw_bias_walk_deg_per_sqrt_s = ins.get<double>("yaw_bias_walk_deg_per_sqrt_s", o.ins.yaw_bias_walk_deg_per_sqrt_s);
  o.ins.roll_pitch_gm_sigma_deg = ins.get<double>("roll_pitch_gm_sigma_deg", o.ins.roll_pitch_gm_sigma_deg);
  o.ins.roll_pitch_gm_tau_s = ins.get<double>("roll_pitch_gm_tau_s", o.ins.roll_pitch_gm_tau_s);
  o.ins.yaw_gm_sigma_deg = ins.get<double>("yaw_gm_sigma_deg", o.ins.yaw_gm_sigma_deg);
  o.ins.yaw_gm_tau_s = ins.get<double>("yaw_gm_tau_s", o.ins.yaw_gm_tau_s);
  const Config alt = s.section_or_empty("altimeter");
  alt.require_known_keys({"rate_hz", "noise_m", "noise_pct", "dropout_probability", "max_range_m", "scale", "bias_m",
                          "beam_misalignment_deg", "lever_arm_m"});
  o.altimeter.rate_hz = alt.get<double>("rate_hz", o.altimeter.rate_hz);
  o.altimeter.noise_m = alt.get<double>("noise_m", o.altimeter.noise_m);
  o.altimeter.noise_pct = alt.get<double>("noise_pct", o.altimeter.noise_pct);
  o.altimeter.dropout_probability = alt.get<double>("dropout_probability", o.altimeter.dropout_probability);
  o.altimeter.max_range_m = alt.get<double>("max_range_m", o.altimeter.max_range_m);
  o.altimeter.scale = alt.get<double>("scale", o.altimeter.scale);
  o.altimeter.bias_m = alt.get<double>("bias_m", o.altimeter.bias_m);
  o.altimeter.beam_misalignment_deg = get_list(alt, "beam_misalignment_deg", o.altimeter.beam_misalignment_deg);
  o.altimeter.lever_arm_m = get_list(alt, "lever_arm_m", o.altimeter.lever_arm_m);
  const Config cam = s.section_or_empty("camera");
  cam.require_known_keys({"trigger_jitter_us", "frame_drop_probability", "pixel_noise_dn", "exposure_us", "gain_db",
                          "boresight_rpy_deg", "time_offset_us", "trigger_latency_us", "focal_scale",
                          "distortion_error", "lever_arm_m"});
  o.camera.trigger_jitter_us = cam.get<double>("trigger_jitter_us", o.camera.trigger_jitter_us);
  o.camera.frame_drop_probability = cam.get<double>("frame_drop_probability", o.camera.frame_drop_probability);
  o.camera.pixel_noise_dn = cam.get<double>("pixel_noise_dn", o.camera.pixel_noise_dn);
  o.camera.exposure_us = cam.get<double>("exposure_us", o.camera.exposure_us);
  o.camera.gain_db = cam.get<double>("gain_db", o.camera.gain_db);
  o.camera.boresight_rpy_deg = get_list(cam, "boresight_rpy_deg", o.camera.boresight_rpy_deg);
  o.camera.time_offset_us = cam.get<double>("time_offset_us", o.camera.time_offset_us);
  o.camera.trigger_latency_us = cam.get<double>("trigger_latency_us", o.camera.trigger_latency_us);
  o.camera.focal_scale = cam.get<double>("focal_scale", o.camera.focal_scale);
  o.camera.distortion_error = get_list(cam, "distortion_error", o.camera.distortion_error);
  o.camera.lever_arm_m = get_list(cam, "lever_arm_m", o.camera.lever_arm_m);
  // Range errors name the set's file and the dotted key.
  o.Check();
  return o;
}

void SensorOptions::Check() const {
  const std::string src = source.empty() ? "sensor options" : source;
  const std::string prefix = set_name.empty() ? "" : set_name + ".";
  const SensorOptions& c = *this;
  auto check = [&](bool ok, const std::string& key, const std::string& what) {
    require_option(ok, src, prefix + key, what);
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
  check(c.ins.yaw_gm_sigma_deg >= 0 && c.ins.yaw_gm_sigma_deg <= 10, "ins.yaw_gm_sigma_deg", "must be in [0, 10]");
  check(c.ins.yaw_gm_tau_s >= 0.01 && c.ins.yaw_gm_tau_s <= 1e5, "ins.yaw_gm_tau_s", "must be in [0.01, 1e5]");
  check(c.altimeter.rate_hz >= 0.1 && c.altimeter.rate_hz <= 1000, "altimeter.rate_hz", "must be in [0.1, 1000]");
  check(c.altimeter.noise_m >= 0 && c.altimeter.noise_m <= 100, "altimeter.noise_m", "must be in [0, 100]");
  check(c.altimeter.noise_pct >= 0 && c.altimeter.noise_pct <= 20, "altimeter.noise_pct", "must be in [0, 20]");
  check(c.altimeter.dropout_probability >= 0 && c.altimeter.dropout_probability <= 1, "altimeter.dropout_probability",
        "must be in [0, 1]");
  check(c.altimeter.max_range_m >= 10 && c.altimeter.max_range_m <= 1e5, "altimeter.max_range_m", "must be in [10, 1e5]");
  check(c.altimeter.scale >= 0.5 && c.altimeter.scale <= 2, "altimeter.scale", "must be in [0.5, 2]");
  check(std::fabs(c.altimeter.bias_m) <= 100, "altimeter.bias_m", "must be in [-100, 100]");
  check(all_within(c.altimeter.beam_misalignment_deg, 10), "altimeter.beam_misalignment_deg",
        "must be in [-10, 10] per axis");
  check(all_within(c.altimeter.lever_arm_m, 20), "altimeter.lever_arm_m", "must be in [-20, 20] per axis");
  check(c.camera.trigger_jitter_us >= 0 && c.camera.trigger_jitter_us <= 5000, "camera.trigger_jitter_us", "must be in [0, 5000]");
  check(c.camera.frame_drop_probability >= 0 && c.camera.frame_drop_probability <= 0.5, "camera.frame_drop_probability",
        "must be in [0, 0.5]");
  check(c.camera.pixel_noise_dn >= 0 && c.camera.pixel_noise_dn <= 50, "camera.pixel_noise_dn", "must be in [0, 50]");
  check(c.camera.exposure_us > 0 && c.camera.exposure_us <= 1e6, "camera.exposure_us", "must be in (0, 1e6]");
  check(c.camera.gain_db >= 0 && c.camera.gain_db <= 48, "camera.gain_db", "must be in [0, 48]");
  check(all_within(c.camera.boresight_rpy_deg, 10), "camera.boresight_rpy_deg", "must be in [-10, 10] per axis");
  check(std::fabs(c.camera.time_offset_us) <= 50000, "camera.time_offset_us", "must be in [-50000, 50000]");
  check(c.camera.trigger_latency_us >= 0 && c.camera.trigger_latency_us <= 50000, "camera.trigger_latency_us",
        "must be in [0, 50000]");
  check(c.camera.focal_scale >= 0.8 && c.camera.focal_scale <= 1.25, "camera.focal_scale", "must be in [0.8, 1.25]");
  check(all_within(c.camera.distortion_error, 1), "camera.distortion_error", "must be in [-1, 1] per coefficient");
  check(all_within(c.camera.lever_arm_m, 20), "camera.lever_arm_m", "must be in [-20, 20] per axis");
}

bool SensorOptions::has_installation_errors() const {
  return altimeter.scale != 1.0 || altimeter.bias_m != 0.0 || any_nonzero(altimeter.beam_misalignment_deg) ||
         any_nonzero(altimeter.lever_arm_m) || any_nonzero(camera.boresight_rpy_deg) || camera.time_offset_us != 0.0 ||
         camera.trigger_latency_us != 0.0 || camera.focal_scale != 1.0 || any_nonzero(camera.distortion_error) ||
         any_nonzero(camera.lever_arm_m);
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
  if (ins.yaw_gm_sigma_deg > 0) {
    out << YAML::Key << "yaw_gm_sigma_deg" << YAML::Value << ins.yaw_gm_sigma_deg;
    out << YAML::Key << "yaw_gm_tau_s" << YAML::Value << ins.yaw_gm_tau_s;
  }
  out << YAML::EndMap;
  out << YAML::Key << "altimeter" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rate_hz" << YAML::Value << altimeter.rate_hz;
  out << YAML::Key << "noise_m" << YAML::Value << altimeter.noise_m;
  out << YAML::Key << "noise_pct" << YAML::Value << altimeter.noise_pct;
  out << YAML::Key << "dropout_probability" << YAML::Value << altimeter.dropout_probability;
  out << YAML::Key << "max_range_m" << YAML::Value << altimeter.max_range_m;
  const bool errors = has_installation_errors();  // only when used: existing sets log as they did
  if (errors) {
    out << YAML::Key << "scale" << YAML::Value << altimeter.scale;
    out << YAML::Key << "bias_m" << YAML::Value << altimeter.bias_m;
    emit_list(out, "beam_misalignment_deg", altimeter.beam_misalignment_deg);
    emit_list(out, "lever_arm_m", altimeter.lever_arm_m);
  }
  out << YAML::EndMap;
  out << YAML::Key << "camera" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "trigger_jitter_us" << YAML::Value << camera.trigger_jitter_us;
  out << YAML::Key << "frame_drop_probability" << YAML::Value << camera.frame_drop_probability;
  out << YAML::Key << "pixel_noise_dn" << YAML::Value << camera.pixel_noise_dn;
  out << YAML::Key << "exposure_us" << YAML::Value << camera.exposure_us;
  out << YAML::Key << "gain_db" << YAML::Value << camera.gain_db;
  if (errors) {
    emit_list(out, "boresight_rpy_deg", camera.boresight_rpy_deg);
    out << YAML::Key << "time_offset_us" << YAML::Value << camera.time_offset_us;
    out << YAML::Key << "trigger_latency_us" << YAML::Value << camera.trigger_latency_us;
    out << YAML::Key << "focal_scale" << YAML::Value << camera.focal_scale;
    emit_list(out, "distortion_error", camera.distortion_error);
    emit_list(out, "lever_arm_m", camera.lever_arm_m);
  }
  out << YAML::EndMap;
  out << YAML::EndMap;
  return out.c_str();
}

}  // namespace nadir::sim
