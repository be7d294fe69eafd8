#include "processes/sim/simulator.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/channels.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/trigger_t.hpp"
#include "processes/sim/ray_caster.h"
#include "processes/sim/sim_rotation.h"

namespace nadir::sim {
namespace {

template <class Msg>
void encode(const Msg& msg, SimEvent* e) {
  e->data.resize(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(e->data.data(), 0, static_cast<int>(e->data.size()));
}

int64_t tick_us(int64_t k, double rate_hz) { return static_cast<int64_t>(std::llround(k * 1e6 / rate_hz)); }

// GPS time of a Unix time: GPS epoch 1980-01-06, 18 leap seconds since.
constexpr int64_t kGpsEpochUnixUs = 315964800LL * 1000000LL;
constexpr int64_t kLeapUs = 18LL * 1000000LL;
constexpr int64_t kWeekUs = 604800LL * 1000000LL;

bool nonzero(const std::array<double, 3>& v) { return v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0; }

}  // namespace

// The camera as it really is: the configured one with the sensor set's
// installation and intrinsic errors applied (each only when set, so an exact
// set renders bit for bit as before).
SimCamera true_camera(const SimCamera& configured, const CameraSensorOptions& errors) {
  SimCamera cam = configured;
  const auto& b = errors.boresight_rpy_deg;
  if (nonzero(b)) cam.body_from_camera = configured.body_from_camera * world_from_body(deg2rad(b[0]), deg2rad(b[1]), deg2rad(b[2]));
  if (errors.focal_scale != 1.0) {
    cam.fx *= errors.focal_scale;
    cam.fy *= errors.focal_scale;
  }
  cam.distortion.resize(5, 0.0);
  bool distorted = false;
  for (size_t i = 0; i < 5; ++i) {
    cam.distortion[i] += errors.distortion_error[i];
    distorted = distorted || errors.distortion_error[i] != 0.0;
  }
  if (!distorted) cam.distortion = configured.distortion;
  return cam;
}

Simulator::Simulator(const FlightProfile& profile, const SimCamera& camera, const SensorOptions& sensors,
                     const SimulatorOptions& options)
    : profile_(profile),
      configured_camera_(camera),
      sensors_(sensors),
      camera_(true_camera(camera, sensors.camera)),
      options_(options),
      terrain_([&] {
        TerrainOptions t = profile.terrain;
        t.seed = options.seed;
        return t;
      }()),
      trajectory_(profile, options.seed),
      renderer_(camera_, terrain_,
                [&] {
                  RendererOptions r;
                  r.pixel_noise_dn = sensors.camera.pixel_noise_dn;
                  r.gain = std::pow(10.0, sensors.camera.gain_db / 20.0);
                  return r;
                }()),
      ins_track_({profile.reference_latitude_deg, profile.reference_longitude_deg, profile.reference_height_m}),
      trigger_rng_(options.seed, 1),
      ins_rng_(options.seed, 2),
      altimeter_rng_(options.seed, 3),
      ins_gm_rng_(options.seed, 7),
      ins_yaw_gm_rng_(options.seed, 8),
      roll_gm_(deg2rad(sensors.ins.roll_pitch_gm_sigma_deg), sensors.ins.roll_pitch_gm_tau_s),
      pitch_gm_(deg2rad(sensors.ins.roll_pitch_gm_sigma_deg), sensors.ins.roll_pitch_gm_tau_s),
      yaw_gm_(deg2rad(sensors.ins.yaw_gm_sigma_deg), sensors.ins.yaw_gm_tau_s) {
  sensors_.Check();
  duration_s_ = options.duration_s > 0 ? std::min(options.duration_s, trajectory_.duration_s()) : trajectory_.duration_s();
  duration_us_ = static_cast<int64_t>(std::floor(duration_s_ * 1e6));
  yaw_bias_rad_ = deg2rad(sensors_.ins.yaw_bias_initial_deg);
  roll_gm_.start(&ins_gm_rng_);  // in the stationary distribution
  pitch_gm_.start(&ins_gm_rng_);
  yaw_gm_.start(&ins_yaw_gm_rng_);
  const auto& mis = sensors_.altimeter.beam_misalignment_deg;
  altimeter_beam_body_ = configured_camera_.optical_axis_body();
  if (mis[0] != 0.0 || mis[1] != 0.0)
    altimeter_beam_body_ = (rot_y(deg2rad(mis[1])) * rot_x(deg2rad(mis[0])) * altimeter_beam_body_).normalized();

  YAML::Node root;
  root["name"] = "sim";
  root["seed"] = static_cast<unsigned long long>(options.seed);
  root["duration_s"] = duration_s_;
  root["profile"] = YAML::Load(profile.yaml);
  for (const std::string& key : profile.overrides) root["profile_overrides"].push_back(key);
  root["sensors"] = YAML::Load(sensors_.to_yaml());
  if (!options.camera_yaml.empty()) root["camera"] = YAML::Load(options.camera_yaml);
  for (const SensorOutage& o : options.outages) {
    YAML::Node outage;
    outage["kind"] = o.name();
    outage["start_s"] = o.start_s;
    outage["duration_s"] = o.duration_s;
    if (o.kind == SensorOutage::Kind::kTexture) outage["contrast"] = o.contrast;
    root["outages"].push_back(outage);
  }
  YAML::Emitter out;
  out << root;
  config_yaml_ = out.c_str();

  queue_.push({options_.epoch_us, kConfig, 0});
  schedule_frame(0);
  schedule_ins(0);
  schedule_altimeter(0);
}

void Simulator::schedule_frame(int64_t k) {
  // The trigger is stamped on the tick (+ jitter); the exposure happens the
  // camera's time offset + trigger latency later.
  const int64_t tick = tick_us(k, camera_.rate_hz);
  const int64_t true_us = tick + static_cast<int64_t>(std::llround(sensors_.camera.exposure_delay_us()));
  if (true_us > duration_us_) return;
  if (true_us < 0) {  // a negative offset: exposure before the run starts, no such frame
    schedule_frame(k + 1);
    return;
  }
  FrameDraw f;
  f.true_us = true_us;
  const double limit = 0.25e6 / camera_.rate_hz;  // keeps frames in order whatever the draw
  const double jitter = std::max(-limit, std::min(limit, sensors_.camera.trigger_jitter_us * trigger_rng_.normal()));
  f.reported_us = tick + static_cast<int64_t>(std::llround(jitter));
  f.dropped = trigger_rng_.bernoulli(sensors_.camera.frame_drop_probability);
  if (static_cast<int64_t>(frames_.size()) <= k) frames_.resize(static_cast<size_t>(k) + 1);
  frames_[static_cast<size_t>(k)] = f;
  const int64_t e = options_.epoch_us;
  queue_.push({e + f.reported_us, kTrigger, k});
  if (!f.dropped && options_.render_images) queue_.push({e + f.reported_us, kImage, k});
  queue_.push({e + f.true_us, kFrameTruth, k});
}

void Simulator::schedule_ins(int64_t k) {
  const int64_t t = tick_us(k, sensors_.ins.rate_hz);
  if (t > duration_us_) return;
  queue_.push({options_.epoch_us + t, kIns, k});
  queue_.push({options_.epoch_us + t, kInsTruth, k});
}

void Simulator::schedule_altimeter(int64_t k) {
  const int64_t t = tick_us(k, sensors_.altimeter.rate_hz);
  if (t > duration_us_) return;
  queue_.push({options_.epoch_us + t, kAltimeter, k});
}

void Simulator::warm_up() {
  if (!options_.render_images) return;
  const TruthState s = trajectory_.at(0.0);
  std::vector<uint8_t> scratch;
  renderer_.render(s.position_ned, s.world_from_body() * camera_.body_from_camera, 0, &scratch);
}

void Simulator::set_epoch(int64_t epoch_us) {
  if (started_) throw std::logic_error("Simulator::set_epoch after the run started");
  std::vector<Pending> pending;
  while (!queue_.empty()) {
    pending.push_back(queue_.top());
    queue_.pop();
  }
  for (Pending& p : pending) {
    p.utime += epoch_us - options_.epoch_us;
    queue_.push(p);
  }
  options_.epoch_us = epoch_us;
}

bool Simulator::next(SimEvent* e) {
  while (!queue_.empty()) {
    const Pending p = queue_.top();
    queue_.pop();
    started_ = true;
    e->utime = p.utime;
    sim_time_s_ = std::max(sim_time_s_, (p.utime - options_.epoch_us) * 1e-6);
    if (make(p, e)) return true;
    ++counts_.outage_messages;
  }
  return false;
}

bool Simulator::make(const Pending& p, SimEvent* e) {
  switch (p.kind) {
    case kConfig:
      make_config(e);
      break;
    case kTrigger:
      make_trigger(p.index, e);
      schedule_frame(p.index + 1);
      break;
    case kImage:
      if (outage(SensorOutage::Kind::kCamera, frames_[static_cast<size_t>(p.index)].true_us)) return false;
      make_image(p.index, e);
      break;
    case kFrameTruth:
      make_truth(frames_[static_cast<size_t>(p.index)].true_us, ground_truth_t::KIND_FRAME, e);
      break;
    case kIns:
      make_ins(p.index, e);  // drawn also when withheld: the noise after the outage is unchanged
      schedule_ins(p.index + 1);
      if (outage(SensorOutage::Kind::kIns, tick_us(p.index, sensors_.ins.rate_hz))) return false;
      break;
    case kInsTruth:
      make_truth(tick_us(p.index, sensors_.ins.rate_hz), ground_truth_t::KIND_INS, e);
      break;
    case kAltimeter:
      make_altimeter(p.index, e);
      schedule_altimeter(p.index + 1);
      break;
  }
  return true;
}

void Simulator::make_config(SimEvent* e) {
  e->channel = channels::kConfig;
  config_t msg;
  msg.utime = options_.epoch_us;
  msg.name = "sim";
  msg.source = profile_.source;
  msg.yaml = config_yaml_;
  encode(msg, e);
}

void Simulator::make_trigger(int64_t k, SimEvent* e) {
  const FrameDraw& f = frames_[static_cast<size_t>(k)];
  e->channel = channels::kCameraTrigger;
  trigger_t msg;
  msg.utime = options_.epoch_us + f.reported_us;
  msg.device_utime = f.reported_us;  // the simulated GPIO clock starts at 0
  msg.sequence = k;
  msg.edge = trigger_t::EDGE_RISING;
  msg.flags = 0;
  ++counts_.frames;
  if (f.dropped) ++counts_.dropped_frames;
  encode(msg, e);
}

void Simulator::make_image(int64_t k, SimEvent* e) {
  const FrameDraw& f = frames_[static_cast<size_t>(k)];
  // The image shows the scene at the TRUE exposure time; it is stamped with
  // the reported trigger time, as the real driver does.
  const TruthState s = trajectory_.at(f.true_us * 1e-6);
  const Eigen::Matrix3d world_from_camera = s.world_from_body() * camera_.body_from_camera;
  Eigen::Vector3d camera_ned = s.position_ned;  // the trajectory is the INS's
  const auto& lever = sensors_.camera.lever_arm_m;
  if (nonzero(lever)) camera_ned += s.world_from_body() * Eigen::Vector3d(lever[0], lever[1], lever[2]);
  renderer_.render(camera_ned, world_from_camera, options_.seed * 0x100000001b3ULL + static_cast<uint64_t>(k),
                   &image_buffer_);
  counts_.marched_pixels += renderer_.last_stats().marched_pixels;
  if (const SensorOutage* o = outage(SensorOutage::Kind::kTexture, f.true_us)) {
    cut_contrast(o->contrast, &image_buffer_);
    ++counts_.outage_messages;
  }
  image_t msg;
  msg.utime = options_.epoch_us + f.reported_us;
  msg.trigger_utime = msg.utime;
  msg.frame_counter = k;
  msg.trigger_sequence = k;
  msg.width = camera_.width;
  msg.height = camera_.height;
  msg.stride = camera_.width;
  msg.pixel_format = image_t::PIXEL_MONO8;
  msg.time_quality = image_t::TIME_SIMULATED;
  msg.exposure_us = static_cast<float>(sensors_.camera.exposure_us);
  msg.gain_db = static_cast<float>(sensors_.camera.gain_db);
  msg.size = static_cast<int32_t>(image_buffer_.size());
  msg.data = image_buffer_;
  e->channel = channels::kCameraImage;
  ++counts_.images;
  encode(msg, e);
}

void Simulator::make_truth(int64_t t_us, int8_t kind, SimEvent* e) {
  const TruthState s = trajectory_.at(t_us * 1e-6);
  ground_truth_t msg;
  msg.utime = options_.epoch_us + t_us;
  msg.kind = kind;
  for (int i = 0; i < 3; ++i) {
    msg.position_ned[i] = s.position_ned[i];
    msg.velocity_ned[i] = s.velocity_ned[i];
  }
  msg.roll = s.roll;
  msg.pitch = s.pitch;
  msg.yaw = s.yaw;
  msg.terrain_height_m = terrain_.height(s.position_ned.x(), s.position_ned.y());
  msg.height_agl_m = -s.position_ned.z() - msg.terrain_height_m;
  e->channel = channels::kGroundTruth;
  ++counts_.ground_truth;
  encode(msg, e);
}

void Simulator::make_ins(int64_t k, SimEvent* e) {
  const int64_t t_us = tick_us(k, sensors_.ins.rate_hz);
  const TruthState s = trajectory_.at(t_us * 1e-6);
  // Yaw bias: random walk, advanced once per sample in order.
  if (last_ins_k_ >= 0) {
    const double dt = (t_us - tick_us(last_ins_k_, sensors_.ins.rate_hz)) * 1e-6;
    yaw_bias_rad_ += deg2rad(sensors_.ins.yaw_bias_walk_deg_per_sqrt_s) * std::sqrt(dt) * ins_rng_.normal();
    roll_gm_.step(dt, &ins_gm_rng_);
    pitch_gm_.step(dt, &ins_gm_rng_);
    yaw_gm_.step(dt, &ins_yaw_gm_rng_);
  }
  last_ins_k_ = k;
  const double rp_sigma = deg2rad(sensors_.ins.roll_pitch_noise_deg);
  const double yaw_sigma = deg2rad(sensors_.ins.yaw_noise_deg);
  ins_t msg;
  msg.utime = options_.epoch_us + t_us;
  const int64_t gps_us = msg.utime - kGpsEpochUnixUs + kLeapUs;
  msg.device_utime = gps_us;
  msg.gps_week = static_cast<int32_t>(gps_us / kWeekUs);
  msg.gps_seconds = static_cast<double>(gps_us % kWeekUs) * 1e-6;
  msg.roll = s.roll + rp_sigma * ins_rng_.normal();
  msg.pitch = s.pitch + rp_sigma * ins_rng_.normal();
  if (roll_gm_.on()) {
    msg.roll += roll_gm_.value();
    msg.pitch += pitch_gm_.value();
  }
  const double yaw_white = yaw_sigma * ins_rng_.normal();
  msg.yaw = yaw_gm_.on() ? wrap_pi(s.yaw + yaw_bias_rad_ + yaw_gm_.value() + yaw_white)
                         : wrap_pi(s.yaw + yaw_bias_rad_ + yaw_white);
  msg.has_rates = true;
  for (int i = 0; i < 3; ++i) {
    msg.angular_rate[i] = s.angular_rate_body[i];
    msg.velocity_ned[i] = s.velocity_ned[i];
    msg.velocity_stddev[i] = 0.0;
    msg.position_stddev[i] = 0.0;
  }
  // The flat world laid on the globe as a vehicle's dead-reckoned path from
  // the profile's reference point (common/geodetic.h).
  const GeodeticPoint geo = ins_track_.geodetic(s.position_ned);
  msg.latitude_deg = geo.latitude_deg;
  msg.longitude_deg = geo.longitude_deg;
  msg.height_m = geo.height_m;
  msg.ins_status = 3;  // NovAtel INS_SOLUTION_GOOD
  msg.flags = ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD | ins_t::FLAG_SIMULATED;
  msg.has_stddev = true;
  msg.attitude_stddev[0] = rp_sigma;
  msg.attitude_stddev[1] = rp_sigma;
  msg.attitude_stddev[2] = yaw_sigma;
  e->channel = channels::kIns;
  ++counts_.ins;
  encode(msg, e);
}

bool Simulator::altimeter_truth_range(double t, double* range_m) const {
  const TruthState s = trajectory_.at(t);
  const Eigen::Vector3d beam_world = s.world_from_body() * altimeter_beam_body_;
  Eigen::Vector3d origin = s.position_ned;
  const auto& lever = sensors_.altimeter.lever_arm_m;
  if (nonzero(lever)) origin += s.world_from_body() * Eigen::Vector3d(lever[0], lever[1], lever[2]);
  RayHit hit;
  if (!cast_ray(terrain_, origin, beam_world.normalized(), -1.0, &hit)) return false;
  *range_m = hit.t;
  return true;
}

void Simulator::make_altimeter(int64_t k, SimEvent* e) {
  const int64_t t_us = tick_us(k, sensors_.altimeter.rate_hz);
  altimeter_t msg;
  msg.utime = options_.epoch_us + t_us;
  // Reported: the nominal beam (the configured optical axis); the true one may be misaligned.
  const Eigen::Vector3d beam = configured_camera_.optical_axis_body().normalized();
  for (int i = 0; i < 3; ++i) msg.beam_body[i] = beam[i];
  double range = 0.0;
  const bool hit = altimeter_truth_range(t_us * 1e-6, &range);
  // Draw both deviates every sample so the noise sequence does not depend on dropouts.
  const double noise = altimeter_rng_.normal();
  const bool dropout = altimeter_rng_.bernoulli(sensors_.altimeter.dropout_probability);
  const bool withheld = outage(SensorOutage::Kind::kAltimeter, t_us) != nullptr;
  if (dropout || withheld) {
    msg.range_m = 0.0;
    msg.signal_quality = 0.0f;
    msg.validity = altimeter_t::VALID_NO_RETURN;
    ++(dropout ? counts_.altimeter_dropouts : counts_.outage_messages);
  } else if (!hit || range > sensors_.altimeter.max_range_m) {
    msg.range_m = 0.0;
    msg.signal_quality = 0.0f;
    msg.validity = altimeter_t::VALID_OUT_OF_RANGE;
  } else {
    const double sigma = sensors_.altimeter.noise_m + 0.01 * sensors_.altimeter.noise_pct * range;
    const AltimeterModelOptions& alt = sensors_.altimeter;
    msg.range_m = (alt.scale != 1.0 || alt.bias_m != 0.0) ? alt.scale * range + alt.bias_m + sigma * noise
                                                          : range + sigma * noise;
    msg.signal_quality = static_cast<float>(std::max(0.1, 1.0 - range / sensors_.altimeter.max_range_m));
    msg.validity = altimeter_t::VALID_OK;
  }
  e->channel = channels::kAltimeter;
  ++counts_.altimeter;
  encode(msg, e);
}

}  // namespace nadir::sim
