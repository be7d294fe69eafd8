#pragma once
// Turns project-frame samples back into what the devices send: NovAtel
// INSPVA (ASCII, short ASCII or binary, with INSSTDEVA at 1 Hz) and
// LightWare-style altimeter lines. The inverse of the bridge's conversion
// (yaw -> azimuth in [0, 360), down -> up velocity, body -> IMU mount).

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "nadir/altimeter_t.hpp"
#include "nadir/ins_t.hpp"
#include "processes/ins_bridge/novatel_encoder.h"

namespace nadir::sim_serial {

enum class InsFormat { kAscii, kShortAscii, kBinary, kMixed };
bool parse_ins_format(const std::string& name, InsFormat* format);

class DeviceFormatter {
 public:
  // imu_to_body_rpy_rad: the mount the bridge is configured with.
  DeviceFormatter(InsFormat format, const Eigen::Vector3d& imu_to_body_rpy_rad, bool with_stddev);

  // Bytes of one INS epoch at GPS time gps_us.
  std::vector<uint8_t> ins_bytes(const ins_t& ins, int64_t gps_us);
  // One altimeter line with CR LF.
  static std::string altimeter_line(const altimeter_t& altimeter);
  // The SPAN body the bridge will decode (for tests and checks).
  ins_bridge::InsPva to_span(const ins_t& ins, int64_t gps_us) const;

 private:
  InsFormat format_;
  Eigen::Matrix3d body_imu_;  // R_imu_body^T
  bool identity_;
  bool with_stddev_;
  int64_t count_ = 0;
  int64_t last_stddev_second_ = -1;
};

}  // namespace nadir::sim_serial
