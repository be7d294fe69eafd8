#include "tools/sim_serial/device_formatter.h"

#include <cmath>
#include <cstdio>

#include "common/geometry.h"
#include "common/gps_time.h"

namespace nadir::sim_serial {

bool parse_ins_format(const std::string& name, InsFormat* format) {
  if (name == "ascii") *format = InsFormat::kAscii;
  else if (name == "short") *format = InsFormat::kShortAscii;
  else if (name == "binary") *format = InsFormat::kBinary;
  else if (name == "mixed") *format = InsFormat::kMixed;
  else return false;
  return true;
}

DeviceFormatter::DeviceFormatter(InsFormat format, const Eigen::Vector3d& imu_to_body_rpy_rad, bool with_stddev)
    : format_(format),
      body_imu_(rotation_from_rpy(imu_to_body_rpy_rad.x(), imu_to_body_rpy_rad.y(), imu_to_body_rpy_rad.z())
                    .transpose()),
      identity_(imu_to_body_rpy_rad.isZero(0.0)),
      with_stddev_(with_stddev) {}

ins_bridge::InsPva DeviceFormatter::to_span(const ins_t& ins, int64_t gps_us) const {
  ins_bridge::InsPva p;
  const int64_t week_us = kSecondsPerWeek * 1000000;
  p.gps_week = static_cast<uint32_t>(gps_us / week_us);
  p.gps_seconds = static_cast<double>(gps_us % week_us) * 1e-6;
  p.latitude_deg = ins.latitude_deg;
  p.longitude_deg = ins.longitude_deg;
  p.height_m = ins.height_m;
  p.north_velocity = ins.velocity_ned[0];
  p.east_velocity = ins.velocity_ned[1];
  p.up_velocity = -ins.velocity_ned[2];
  Eigen::Vector3d rpy(ins.roll, ins.pitch, ins.yaw);
  if (!identity_) {
    // R_ned_imu = R_ned_body * R_imu_body^T: what the receiver reports for its own axes.
    rpy = rpy_from_rotation(rotation_from_rpy(ins.roll, ins.pitch, ins.yaw) * body_imu_);
  }
  p.roll_deg = rad_to_deg(rpy.x());
  p.pitch_deg = rad_to_deg(rpy.y());
  double azimuth = std::fmod(rad_to_deg(rpy.z()), 360.0);
  if (azimuth < 0) azimuth += 360.0;
  p.azimuth_deg = azimuth;
  p.status = ins.ins_status != 0 ? ins.ins_status : ins_bridge::kInsSolutionGood;
  if (ins_bridge::ins_status_name(p.status) == nullptr) p.status = ins_bridge::kInsSolutionGood;
  return p;
}

std::vector<uint8_t> DeviceFormatter::ins_bytes(const ins_t& ins, int64_t gps_us) {
  const ins_bridge::InsPva pva = to_span(ins, gps_us);
  ins_bridge::NovatelHeader header;
  header.gps_week = pva.gps_week;
  header.gps_seconds = pva.gps_seconds;
  header.sequence = static_cast<uint16_t>(count_);
  std::vector<uint8_t> out;
  const int64_t second = gps_us / 1000000;
  if (with_stddev_ && second != last_stddev_second_) {
    last_stddev_second_ = second;
    ins_bridge::InsStdDev s;
    s.gps_week = pva.gps_week;
    s.gps_seconds = pva.gps_seconds;
    // Attitude sigmas: the simulator's own where the log carries them (a
    // receiver reporting its attitude as better than it is makes yaw fusion
    // gate out good INS yaw). Fixed, SPAN-like figures otherwise.
    s.latitude_m = s.longitude_m = 0.02f;
    s.height_m = 0.03f;
    s.north_velocity = s.east_velocity = s.up_velocity = 0.01f;
    s.roll_deg = s.pitch_deg = 0.005f;
    s.azimuth_deg = 0.02f;
    if (ins.has_stddev) {
      s.roll_deg = static_cast<float>(rad_to_deg(ins.attitude_stddev[0]));
      s.pitch_deg = static_cast<float>(rad_to_deg(ins.attitude_stddev[1]));
      s.azimuth_deg = static_cast<float>(rad_to_deg(ins.attitude_stddev[2]));
    }
    const std::string text = ins_bridge::encode_insstdev_ascii(header, s);
    out.assign(text.begin(), text.end());
  }
  InsFormat format = format_;
  if (format == InsFormat::kMixed) format = static_cast<InsFormat>(count_ % 3);
  ++count_;
  if (format == InsFormat::kBinary) {
    const std::vector<uint8_t> b = ins_bridge::encode_inspva_binary(header, pva);
    out.insert(out.end(), b.begin(), b.end());
  } else {
    const std::string text = format == InsFormat::kAscii ? ins_bridge::encode_inspva_ascii(header, pva)
                                                         : ins_bridge::encode_inspvas_ascii(pva);
    out.insert(out.end(), text.begin(), text.end());
  }
  return out;
}

std::string DeviceFormatter::altimeter_line(const altimeter_t& a) {
  char line[64];
  switch (a.validity) {
    case altimeter_t::VALID_NO_RETURN: return "--.--\r\n";
    case altimeter_t::VALID_PARSE_ERROR: return "ERR\r\n";
    default: break;
  }
  if (a.signal_quality >= 0) {
    std::snprintf(line, sizeof line, "%.2f m %d%%\r\n", a.range_m,
                  static_cast<int>(std::lround(std::min(1.0f, a.signal_quality) * 100)));
  } else {
    std::snprintf(line, sizeof line, "%.2f m\r\n", a.range_m);
  }
  return line;
}

}  // namespace nadir::sim_serial
