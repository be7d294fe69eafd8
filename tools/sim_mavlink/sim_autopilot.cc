#include "tools/sim_mavlink/sim_autopilot.h"

#include <Eigen/Geometry>

#include <cmath>

#include "common/geometry.h"

namespace nadir::sim_mavlink {
namespace {

constexpr uint8_t kMavTypeFixedWing = 1;
constexpr uint8_t kMavAutopilotPx4 = 12;
constexpr uint8_t kMavStateActive = 4;
constexpr uint8_t kDistanceSensorLaser = 0;  // MAV_DISTANCE_SENSOR_LASER

uint16_t clamp_cm(double m) { return static_cast<uint16_t>(std::clamp(std::lround(m * 100.0), 0L, 65535L)); }

}  // namespace

SimAutopilot::SimAutopilot(const SimAutopilotOptions& options, int64_t boot_vehicle_us, Send send)
    : options_(options),
      boot_us_(boot_vehicle_us),
      send_(std::move(send)),
      encoder_(static_cast<uint8_t>(options.system_id), static_cast<uint8_t>(options.component_id)) {}

bool SimAutopilot::boot_ms(int64_t utime, uint32_t* ms) {
  if (utime < boot_us_) {
    ++skipped_;
    return false;
  }
  *ms = static_cast<uint32_t>((utime - boot_us_ + 500) / 1000);  // nearest millisecond
  return true;
}

void SimAutopilot::on_ins(const ins_t& ins) {
  uint32_t ms = 0;
  if (!boot_ms(ins.utime, &ms)) return;
  const float rates[3] = {static_cast<float>(ins.has_rates ? ins.angular_rate[0] : 0.0),
                          static_cast<float>(ins.has_rates ? ins.angular_rate[1] : 0.0),
                          static_cast<float>(ins.has_rates ? ins.angular_rate[2] : 0.0)};
  if (options_.quaternion) {
    mavlink::AttitudeQuaternion a;
    a.time_boot_ms = ms;
    const Eigen::Quaterniond q(rotation_from_rpy(ins.roll, ins.pitch, ins.yaw));
    a.q1 = static_cast<float>(q.w());
    a.q2 = static_cast<float>(q.x());
    a.q3 = static_cast<float>(q.y());
    a.q4 = static_cast<float>(q.z());
    a.rollspeed = rates[0];
    a.pitchspeed = rates[1];
    a.yawspeed = rates[2];
    send(a);
    return;
  }
  mavlink::Attitude a;
  a.time_boot_ms = ms;
  a.roll = static_cast<float>(ins.roll);
  a.pitch = static_cast<float>(ins.pitch);
  a.yaw = static_cast<float>(wrap_angle(ins.yaw));
  a.rollspeed = rates[0];
  a.pitchspeed = rates[1];
  a.yawspeed = rates[2];
  send(a);
}

void SimAutopilot::on_altimeter(const altimeter_t& altimeter) {
  uint32_t ms = 0;
  if (!boot_ms(altimeter.utime, &ms)) return;
  mavlink::DistanceSensor d;
  d.time_boot_ms = ms;
  d.min_distance = clamp_cm(options_.min_distance_m);
  d.max_distance = clamp_cm(options_.max_distance_m);
  // No return: one centimetre beyond the maximum, as ArduPilot reports it.
  const bool ok = altimeter.validity == altimeter_t::VALID_OK && std::isfinite(altimeter.range_m);
  d.current_distance = ok ? clamp_cm(altimeter.range_m) : static_cast<uint16_t>(d.max_distance + 1);
  d.type = kDistanceSensorLaser;
  d.orientation = mavlink::kSensorRotationDown;
  d.signal_quality = altimeter.signal_quality < 0 ? 0
                                                  : static_cast<uint8_t>(std::clamp(
                                                        std::lround(altimeter.signal_quality * 100.0f), 2L, 100L));
  send(d);
}

void SimAutopilot::tick(int64_t now_us) {
  if (now_us - last_second_us_ < 1000000) return;
  last_second_us_ = now_us;
  mavlink::Heartbeat hb;
  hb.type = kMavTypeFixedWing;
  hb.autopilot = kMavAutopilotPx4;
  hb.system_status = kMavStateActive;
  send(hb);
  mavlink::SystemTime st;
  st.time_unix_usec = static_cast<uint64_t>(now_us);
  st.time_boot_ms = static_cast<uint32_t>((now_us - boot_us_) / 1000);
  send(st);
}

void SimAutopilot::on_datagram(const uint8_t* data, size_t size, int64_t now_us) {
  std::vector<mavlink::Frame> frames;
  parser_.feed(data, size, now_us, 0.0, &frames);
  parser_.end_of_datagram(&frames);
  companion_.rejected_spans = parser_.counts().rejected_spans;
  for (const mavlink::Frame& frame : frames) {
    const mavlink::MessageInfo* info = mavlink::find_message(frame.msgid);
    ++companion_.received[info ? info->name : "?"];
    if (frame.msgid == mavlink::TimeSync::kId) {
      const mavlink::TimeSync request = frame.decode<mavlink::TimeSync>();
      if (request.tc1 != 0) continue;
      mavlink::TimeSync answer;
      answer.tc1 = (now_us - boot_us_) * 1000;  // boot time in ns, as PX4's hrt
      answer.ts1 = request.ts1;
      answer.target_system = frame.sysid;
      answer.target_component = frame.compid;
      send(answer);
      ++companion_.timesync_answered;
    } else if (frame.msgid == mavlink::VisionPositionEstimate::kId) {
      companion_.last_reset_counter = frame.decode<mavlink::VisionPositionEstimate>().reset_counter;
    }
  }
}

}  // namespace nadir::sim_mavlink
