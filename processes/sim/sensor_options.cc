#include "processes/sim/sensor_options.h"

#include <yaml-cpp/yaml.h>

#include <cmath>

namespace nadir::sim {
namespace {

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

const OptionsSchema<SensorOptions>& SensorOptions::schema() {
  using O = SensorOptions;
  using I = InsModelOptions;
  using A = AltimeterModelOptions;
  using C = CameraSensorOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("sim_sensors.<set>", "A sensor set of config/sim_sensors.yaml (nadir_sim --sensor-set): the "
                                            "simulated INS, altimeter and camera errors.");
    s.number("ins.rate_hz", 1.0, 1000.0, "Hz", "INS sample rate", &O::ins, &I::rate_hz)
        .number("ins.roll_pitch_noise_deg", 0.0, 10.0, "deg", "white noise sigma on roll and pitch", &O::ins,
                &I::roll_pitch_noise_deg)
        .number("ins.yaw_noise_deg", 0.0, 10.0, "deg", "white noise sigma on yaw", &O::ins, &I::yaw_noise_deg)
        .number("ins.yaw_bias_initial_deg", -30.0, 30.0, "deg", "yaw bias at the start", &O::ins,
                &I::yaw_bias_initial_deg)
        .number("ins.yaw_bias_walk_deg_per_sqrt_s", 0.0, 1.0, "deg/sqrt(s)", "random-walk drift of the yaw bias",
                &O::ins, &I::yaw_bias_walk_deg_per_sqrt_s)
        .number("ins.roll_pitch_gm_sigma_deg", 0.0, 10.0, "deg", "Gauss-Markov roll/pitch error sigma", &O::ins,
                &I::roll_pitch_gm_sigma_deg)
        .number("ins.roll_pitch_gm_tau_s", 0.01, 1e5, "s", "... its correlation time", &O::ins,
                &I::roll_pitch_gm_tau_s)
        .number("ins.yaw_gm_sigma_deg", 0.0, 10.0, "deg", "Gauss-Markov yaw error sigma", &O::ins,
                &I::yaw_gm_sigma_deg)
        .number("ins.yaw_gm_tau_s", 0.01, 1e5, "s", "... its correlation time", &O::ins, &I::yaw_gm_tau_s)
        .number("altimeter.rate_hz", 0.1, 1000.0, "Hz", "altimeter sample rate", &O::altimeter, &A::rate_hz)
        .number("altimeter.noise_m", 0.0, 100.0, "m", "range noise sigma, constant part", &O::altimeter,
                &A::noise_m)
        .number("altimeter.noise_pct", 0.0, 20.0, "%", "... plus this percentage of the range", &O::altimeter,
                &A::noise_pct)
        .number("altimeter.dropout_probability", 0.0, 1.0, "", "published as VALID_NO_RETURN", &O::altimeter,
                &A::dropout_probability)
        .number("altimeter.max_range_m", 10.0, 1e5, "m", "beyond: VALID_OUT_OF_RANGE", &O::altimeter,
                &A::max_range_m)
        .number("altimeter.scale", 0.5, 2.0, "", "reported range = scale * true range + bias_m + noise",
                &O::altimeter, &A::scale)
        .number("altimeter.bias_m", -100.0, 100.0, "m", "range bias", &O::altimeter, &A::bias_m)
        .numbers<2>("altimeter.beam_misalignment_deg", -10.0, 10.0, "deg", "true beam's roll, pitch from the reported",
                    &O::altimeter, &A::beam_misalignment_deg)
        .numbers<3>("altimeter.lever_arm_m", -20.0, 20.0, "m", "beam origin from the INS, body frame",
                    &O::altimeter, &A::lever_arm_m)
        .number("camera.trigger_jitter_us", 0.0, 5000.0, "us", "sigma of reported trigger time - true exposure time",
                &O::camera, &C::trigger_jitter_us)
        .number("camera.frame_drop_probability", 0.0, 0.5, "", "trigger published, image not", &O::camera,
                &C::frame_drop_probability)
        .number("camera.pixel_noise_dn", 0.0, 50.0, "DN", "pixel noise sigma", &O::camera, &C::pixel_noise_dn)
        .above("camera.exposure_us", 0.0, 1e6, "us", "exposure time (motion blur)", &O::camera, &C::exposure_us)
        .number("camera.gain_db", 0.0, 48.0, "dB", "sensor gain", &O::camera, &C::gain_db)
        .numbers<3>("camera.boresight_rpy_deg", -10.0, 10.0, "deg", "true mount = configured mount * R(rpy)",
                    &O::camera, &C::boresight_rpy_deg)
        .number("camera.time_offset_us", -50000.0, 50000.0, "us", "exposure this long after the stamp", &O::camera,
                &C::time_offset_us)
        .number("camera.trigger_latency_us", 0.0, 50000.0, "us", "trigger edge to start of exposure", &O::camera,
                &C::trigger_latency_us)
        .number("camera.focal_scale", 0.8, 1.25, "", "true fx, fy = configured * focal_scale", &O::camera,
                &C::focal_scale)
        .numbers<5>("camera.distortion_error", -1.0, 1.0, "", "true k1, k2, p1, p2, k3 = configured + this",
                    &O::camera, &C::distortion_error)
        .numbers<3>("camera.lever_arm_m", -20.0, 20.0, "m", "camera centre from the INS, body frame", &O::camera,
                    &C::lever_arm_m);
    return s;
  }();
  return schema;
}

SensorOptions SensorOptions::from_config(const Config& root, const std::string& set_name) {
  SensorOptions o;
  o.set_name = set_name;
  o.source = root.source();
  if (!root.has(set_name)) throw root.error(set_name, "is not a sensor set in this file");
  schema().read(root.section(set_name), &o);
  return o;
}

void SensorOptions::Check() const {
  schema().check(*this, Config(YAML::Node(YAML::NodeType::Map), source.empty() ? "sensor options" : source, set_name));
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
