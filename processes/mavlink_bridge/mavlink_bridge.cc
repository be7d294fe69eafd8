#include "processes/mavlink_bridge/mavlink_bridge.h"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

#include "common/channels.h"
#include "common/geometry.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ins_t.hpp"
#include "processes/mavlink_bridge/pose_messages.h"

namespace nadir::mavlink_bridge {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr size_t kTimesyncRequestsKept = 32;

bool finite_all(std::initializer_list<double> values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

ins_t empty_ins() {
  ins_t msg{};
  for (int i = 0; i < 3; ++i) {
    msg.velocity_ned[i] = kNaN;
    msg.angular_rate[i] = kNaN;
  }
  msg.latitude_deg = msg.longitude_deg = msg.height_m = kNaN;
  return msg;
}

}  // namespace

MavlinkBridge::MavlinkBridge(const BridgeOptions& options, Bus& bus, Send send)
    : options_(options),
      bus_(bus),
      send_(std::move(send)),
      encoder_(static_cast<uint8_t>(options.system_id), static_cast<uint8_t>(options.component_id)),
      clock_(options.input.clock_sync),
      autopilot_sysid_(options.input.autopilot_system_id),
      gps_track_({options.output.gps_input.origin_latitude_deg, options.output.gps_input.origin_longitude_deg,
                  options.output.gps_input.origin_altitude_m}) {
  options_.Check();
}

int MavlinkBridge::on_bytes(const uint8_t* data, size_t size, int64_t arrival_us, double byte_time_us,
                            bool datagram) {
  frames_.clear();
  parser_.feed(data, size, arrival_us, byte_time_us, &frames_);
  if (datagram) parser_.end_of_datagram(&frames_);
  int from_autopilot = 0;
  for (const mavlink::Frame& frame : frames_) from_autopilot += handle(frame) ? 1 : 0;
  return from_autopilot;
}

void MavlinkBridge::on_link_reopened() {
  parser_.reset();
  clock_.restart("MAVLink link reopened");
}

bool MavlinkBridge::handle(const mavlink::Frame& frame) {
  using namespace mavlink;
  if (frame.sysid == options_.system_id && frame.compid == options_.component_id) return false;  // our own echo
  if (frame.msgid == Heartbeat::kId) {
    const Heartbeat hb = frame.decode<Heartbeat>();
    ++in_.heartbeats;
    // The first system that says it is an autopilot is the one we listen to.
    if (autopilot_sysid_ == 0 && hb.autopilot != kMavAutopilotInvalid) autopilot_sysid_ = frame.sysid;
    return autopilot_sysid_ != 0 && frame.sysid == autopilot_sysid_;
  }
  if (autopilot_sysid_ != 0 && frame.sysid != autopilot_sysid_) {
    ++in_.other_system;
    return false;
  }
  // Before the first autopilot HEARTBEAT any system's frames are taken (and
  // answered): a configured autopilot_system_id narrows that from the start.
  handle_from_autopilot(frame);
  return true;
}

void MavlinkBridge::handle_from_autopilot(const mavlink::Frame& frame) {
  using namespace mavlink;
  switch (frame.msgid) {
    case SystemTime::kId:
      clock_sample(int64_t{frame.decode<SystemTime>().time_boot_ms} * 1000, frame.start_arrival_us);
      return;
    case TimeSync::kId:
      on_timesync(frame);
      return;
    case Attitude::kId: {
      if (options_.input.attitude != "attitude") {
        ++in_.attitude_ignored;
        return;
      }
      const Attitude a = frame.decode<Attitude>();
      const float rates[3] = {a.rollspeed, a.pitchspeed, a.yawspeed};
      on_attitude(a.time_boot_ms, a.roll, a.pitch, a.yaw, rates);
      return;
    }
    case AttitudeQuaternion::kId: {
      if (options_.input.attitude != "attitude_quaternion") {
        ++in_.attitude_ignored;
        return;
      }
      const AttitudeQuaternion a = frame.decode<AttitudeQuaternion>();
      const Eigen::Quaterniond q(a.q1, a.q2, a.q3, a.q4);  // body FRD -> NED
      if (!finite_all({a.q1, a.q2, a.q3, a.q4}) || std::abs(q.norm() - 1.0) > 0.01) {
        ++in_.bad_values;
        return;
      }
      const Eigen::Vector3d rpy = rpy_from_rotation(q.normalized().toRotationMatrix());
      const float rates[3] = {a.rollspeed, a.pitchspeed, a.yawspeed};
      on_attitude(a.time_boot_ms, rpy.x(), rpy.y(), rpy.z(), rates);
      return;
    }
    case DistanceSensor::kId:
      on_distance(frame);
      return;
    case GlobalPositionInt::kId:
    case GpsRawInt::kId:
      on_truth(frame);
      return;
    default:
      ++in_.not_read;
  }
}

void MavlinkBridge::clock_sample(int64_t device_us, int64_t arrival_us) {
  ++in_.clock_samples;
  clock_.add(device_us, arrival_us);
}

void MavlinkBridge::on_timesync(const mavlink::Frame& frame) {
  const mavlink::TimeSync ts = frame.decode<mavlink::TimeSync>();
  if (ts.tc1 == 0) {
    // A request: the autopilot's send time is a clock sample, and it wants
    // ours back (PX4 and ArduPilot map companion timestamps with it).
    clock_sample(ts.ts1 / 1000, frame.start_arrival_us);
    mavlink::TimeSync answer;
    answer.tc1 = frame.start_arrival_us * 1000;
    answer.ts1 = ts.ts1;
    answer.target_system = frame.sysid;
    answer.target_component = frame.compid;
    send(answer);
    ++in_.timesync_answered;
    return;
  }
  for (int64_t sent : timesync_requests_ns_) {
    if (sent == ts.ts1) {
      clock_sample(ts.tc1 / 1000, frame.start_arrival_us);  // the autopilot's time when it answered
      return;
    }
  }
}

void MavlinkBridge::on_attitude(uint32_t time_boot_ms, double roll, double pitch, double yaw, const float rates[3]) {
  if (!finite_all({roll, pitch, yaw, rates[0], rates[1], rates[2]})) {
    ++in_.bad_values;
    return;
  }
  if (!clock_.valid()) {
    ++in_.waiting_for_clock;
    return;
  }
  const int64_t device_us = int64_t{time_boot_ms} * 1000;
  ins_t msg = empty_ins();
  msg.utime = clock_.to_vehicle(device_us);
  msg.device_utime = device_us;
  msg.roll = roll;
  msg.pitch = pitch;
  msg.yaw = wrap_angle(yaw);
  msg.has_rates = true;
  for (int i = 0; i < 3; ++i) msg.angular_rate[i] = rates[i];
  // The autopilot sends attitude only from a running estimator.
  msg.flags = ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD;
  if (clock_.state().settling) msg.flags |= ins_t::FLAG_TIME_JUMP;
  bus_.publish(channels::kIns, msg);
  ++in_.attitude;
}

void MavlinkBridge::on_distance(const mavlink::Frame& frame) {
  const mavlink::DistanceSensor d = frame.decode<mavlink::DistanceSensor>();
  const InputOptions& o = options_.input;
  if (!o.distance_sensor || d.orientation != mavlink::kSensorRotationDown ||
      (o.distance_sensor_id >= 0 && d.id != o.distance_sensor_id)) {
    ++in_.distance_ignored;
    return;
  }
  if (!clock_.valid()) {
    ++in_.waiting_for_clock;
    return;
  }
  altimeter_t msg{};
  msg.utime = clock_.to_vehicle(int64_t{d.time_boot_ms} * 1000) - std::llround(o.distance_latency_ms * 1000.0);
  for (int i = 0; i < 3; ++i) msg.beam_body[i] = o.beam_body[i];
  msg.range_m = d.current_distance / 100.0;
  // signal_quality: 0 unknown, 1 invalid, 2..100 quality in percent.
  msg.signal_quality = d.signal_quality == 0 ? -1.0f : static_cast<float>(d.signal_quality) / 100.0f;
  if (d.current_distance < d.min_distance || d.current_distance > d.max_distance) {
    msg.validity = altimeter_t::VALID_OUT_OF_RANGE;
  } else if (d.signal_quality == 1 || (d.signal_quality > 0 && msg.signal_quality < o.min_signal_quality)) {
    msg.validity = altimeter_t::VALID_LOW_SIGNAL;
  } else {
    msg.validity = altimeter_t::VALID_OK;
  }
  bus_.publish(channels::kAltimeter, msg);
  ++in_.distance;
}

void MavlinkBridge::on_truth(const mavlink::Frame& frame) {
  if (!options_.input.truth) return;
  ins_t msg = empty_ins();
  msg.roll = msg.pitch = msg.yaw = kNaN;  // position only
  if (frame.msgid == mavlink::GlobalPositionInt::kId) {
    const mavlink::GlobalPositionInt g = frame.decode<mavlink::GlobalPositionInt>();
    if (!clock_.valid()) {
      ++in_.waiting_for_clock;
      return;
    }
    msg.device_utime = int64_t{g.time_boot_ms} * 1000;
    msg.utime = clock_.to_vehicle(msg.device_utime);
    msg.latitude_deg = g.lat * 1e-7;
    msg.longitude_deg = g.lon * 1e-7;
    msg.height_m = g.alt * 1e-3;  // AMSL, as GLOBAL_POSITION_INT gives it
    msg.velocity_ned[0] = g.vx * 1e-2;
    msg.velocity_ned[1] = g.vy * 1e-2;
    msg.velocity_ned[2] = g.vz * 1e-2;
  } else {
    const mavlink::GpsRawInt g = frame.decode<mavlink::GpsRawInt>();
    // time_usec is UNIX time or time since boot: told apart by magnitude.
    const int64_t t = static_cast<int64_t>(g.time_usec);
    const bool unix_time = t > int64_t{1000000000} * 1000000;
    if (!unix_time && !clock_.valid()) {
      ++in_.waiting_for_clock;
      return;
    }
    msg.device_utime = t;
    msg.utime = unix_time ? t : clock_.to_vehicle(t);
    msg.latitude_deg = g.lat * 1e-7;
    msg.longitude_deg = g.lon * 1e-7;
    msg.height_m = g.alt * 1e-3;
    if (g.vel != 0xFFFF && g.cog != 0xFFFF) {
      const double speed = g.vel * 1e-2;
      const double course = deg_to_rad(g.cog * 1e-2);
      msg.velocity_ned[0] = speed * std::cos(course);
      msg.velocity_ned[1] = speed * std::sin(course);
    }
    msg.ins_status = g.fix_type;
  }
  bus_.publish(options_.input.truth_channel, msg);
  ++in_.truth;
}

template <class M>
void MavlinkBridge::send(const M& msg) {
  send_(encoder_.encode(msg));
}

bool MavlinkBridge::due(double rate_hz, int64_t utime, int64_t* last_us) const {
  if (rate_hz <= 0) return false;
  // 10 % slack, so that a source at exactly the configured rate is not halved by jitter.
  if (*last_us != 0 && static_cast<double>(utime - *last_us) < 0.9e6 / rate_hz) return false;
  *last_us = utime;
  return true;
}

void MavlinkBridge::on_pose(const pose_t& pose) {
  ++out_.poses;
  const bool initializing = (pose.flags & pose_t::FLAG_INITIALIZING) != 0;
  // A restarted estimator (its frame count starts again) or one that lost
  // its yaw and is initialising again: the position jumps, tell the autopilot.
  if (have_pose_ && (pose.frames < last_frames_ || (initializing && !last_initializing_))) {
    ++reset_counter_;
    ++out_.resets;
    gps_track_.restart();  // the new estimate starts its path again
  }
  have_pose_ = true;
  last_frames_ = pose.frames;
  last_initializing_ = initializing;
  const OutputOptions& o = options_.output;
  // Every POSE moves the track, so GPS_INPUT follows the path at POSE's rate.
  const GeodeticPoint position =
      gps_track_.geodetic(Eigen::Vector3d(pose.position_ned[0], pose.position_ned[1], pose.position_ned[2]));
  if (due(o.vision_position_estimate_hz, pose.utime, &last_vpe_us_)) {
    send(vision_position_estimate(pose, o.attitude_variance_rad2, reset_counter_));
    ++out_.vision_position_estimate;
  }
  if (due(o.odometry_hz, pose.utime, &last_odometry_us_)) {
    send(odometry(pose, o.attitude_variance_rad2, reset_counter_));
    ++out_.odometry;
  }
  if (due(o.gps_input_hz, pose.utime, &last_gps_input_us_)) {
    send(gps_input(pose, position, o.gps_input));
    ++out_.gps_input;
  }
}

void MavlinkBridge::tick(int64_t now_us) {
  const OutputOptions& o = options_.output;
  if (o.heartbeat_hz > 0 && now_us - last_heartbeat_us_ >= static_cast<int64_t>(1e6 / o.heartbeat_hz)) {
    last_heartbeat_us_ = now_us;
    mavlink::Heartbeat hb;
    hb.type = mavlink::kMavTypeOnboardController;
    hb.autopilot = mavlink::kMavAutopilotInvalid;
    hb.system_status = mavlink::kMavStateActive;
    send(hb);
    ++out_.heartbeat;
  }
  if (o.timesync_hz > 0 && now_us - last_timesync_us_ >= static_cast<int64_t>(1e6 / o.timesync_hz)) {
    last_timesync_us_ = now_us;
    mavlink::TimeSync request;
    request.tc1 = 0;
    request.ts1 = now_us * 1000;
    request.target_system = static_cast<uint8_t>(autopilot_sysid_);
    timesync_requests_ns_.push_back(request.ts1);
    if (timesync_requests_ns_.size() > kTimesyncRequestsKept) {
      timesync_requests_ns_.erase(timesync_requests_ns_.begin());
    }
    send(request);
    ++out_.timesync;
  }
}

void MavlinkBridge::report(StatusReport* r) const {
  const mavlink::FrameCounts& f = parser_.counts();
  const ClockSyncState& c = clock_.state();
  r->received += f.accepted() + f.rejected_spans;
  r->published += in_.attitude + in_.distance + in_.truth;
  r->dropped += in_.waiting_for_clock + in_.bad_values;
  auto add = [&](const char* name, double value) { r->counters.emplace_back(name, value); };
  add("mav_bytes", static_cast<double>(f.bytes));
  add("mav_frames_accepted", static_cast<double>(f.accepted()));
  add("mav_frames_v1", static_cast<double>(f.frames_v1));
  add("mav_frames_signed_unverified", static_cast<double>(f.frames_signed));
  add("mav_unknown_skipped", static_cast<double>(f.unknown_skipped));
  add("mav_rejected_spans", static_cast<double>(f.rejected_spans));
  add("mav_garbage_bytes", static_cast<double>(f.garbage_bytes));
  add("mav_rejected_crc", static_cast<double>(f.bad_crc));
  add("mav_rejected_length", static_cast<double>(f.bad_length));
  add("mav_rejected_flags", static_cast<double>(f.bad_flags));
  add("mav_rejected_unknown_id", static_cast<double>(f.unknown_id));
  add("mav_rejected_truncated", static_cast<double>(f.truncated));
  add("autopilot_system", autopilot_sysid_);
  add("in_heartbeats", static_cast<double>(in_.heartbeats));
  add("in_attitude", static_cast<double>(in_.attitude));
  add("in_attitude_ignored", static_cast<double>(in_.attitude_ignored));
  add("in_distance", static_cast<double>(in_.distance));
  add("in_distance_ignored", static_cast<double>(in_.distance_ignored));
  add("in_truth", static_cast<double>(in_.truth));
  add("in_waiting_for_clock", static_cast<double>(in_.waiting_for_clock));
  add("in_bad_values", static_cast<double>(in_.bad_values));
  add("in_other_system", static_cast<double>(in_.other_system));
  add("in_not_read", static_cast<double>(in_.not_read));
  add("in_clock_samples", static_cast<double>(in_.clock_samples));
  add("in_timesync_answered", static_cast<double>(in_.timesync_answered));
  add("out_poses", static_cast<double>(out_.poses));
  add("out_vision_position_estimate", static_cast<double>(out_.vision_position_estimate));
  add("out_odometry", static_cast<double>(out_.odometry));
  add("out_gps_input", static_cast<double>(out_.gps_input));
  add("out_heartbeat", static_cast<double>(out_.heartbeat));
  add("out_timesync", static_cast<double>(out_.timesync));
  add("out_reset_counter", reset_counter_);
  add("clock_valid", c.valid ? 1.0 : 0.0);
  add("clock_offset_us", c.offset_us);
  add("clock_drift_ppm", c.drift_ppm);
  add("clock_samples", static_cast<double>(c.samples));
  add("clock_jumps", static_cast<double>(c.jumps));
  add("clock_settling", c.settling ? 1.0 : 0.0);
  add("clock_flagged_samples", static_cast<double>(c.untrusted));
  add("clock_late_bound_us", c.late_bound_us);
  auto warn = [&](const std::string& why) {
    if (r->state == status_t::STATE_OK) r->state = status_t::STATE_WARN;
    if (!r->detail.empty()) r->detail += "; ";
    r->detail += why;
  };
  if (in_.heartbeats == 0) warn("no HEARTBEAT from an autopilot yet");
  if (!c.valid) warn("autopilot clock not yet mapped (needs SYSTEM_TIME or TIMESYNC)");
}

}  // namespace nadir::mavlink_bridge
