#pragma once
// The MAVLink messages nadir reads and writes, from the MAVLink common message
// set (message_definitions/v1.0/common.xml, with minimal.xml for HEARTBEAT) as
// published in mavlink-mappings 1.0.21-20250824 (the definitions node-mavlink
// 2.3.0 is generated from). Fields are listed in wire order: the base fields
// sorted by type size (largest first, stable), then the MAVLink 2 extension
// fields in definition order after extensions(). CRC_EXTRA is the value in the
// definitions; crc_extra_of<M>() recomputes it from the field list, and a test
// checks both agree, so a field typed or ordered wrongly cannot go unnoticed.
//
// Units are MAVLink's (ms, cm, degE7, ...); converting them is the bridge's job.

#include <array>
#include <cstdint>

namespace nadir::mavlink {

// MAV_DISTANCE_SENSOR orientation MAV_SENSOR_ROTATION_PITCH_270: facing down.
inline constexpr uint8_t kSensorRotationDown = 25;
inline constexpr uint8_t kMavFrameLocalNed = 1;         // MAV_FRAME_LOCAL_NED
inline constexpr uint8_t kMavFrameBodyFrd = 12;         // MAV_FRAME_BODY_FRD
inline constexpr uint8_t kMavEstimatorTypeVio = 3;      // MAV_ESTIMATOR_TYPE_VIO
inline constexpr uint8_t kMavTypeOnboardController = 18;
inline constexpr uint8_t kMavAutopilotInvalid = 8;
inline constexpr uint8_t kMavStateActive = 4;
inline constexpr uint8_t kMavCompIdVio = 197;           // MAV_COMP_ID_VISUAL_INERTIAL_ODOMETRY

struct Heartbeat {
  static constexpr uint32_t kId = 0;
  static constexpr uint8_t kCrcExtra = 50;
  static constexpr const char* kName = "HEARTBEAT";
  uint32_t custom_mode = 0;
  uint8_t type = 0;
  uint8_t autopilot = 0;
  uint8_t base_mode = 0;
  uint8_t system_status = 0;
  uint8_t mavlink_version = 3;
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("custom_mode", s.custom_mode);
    v("type", s.type);
    v("autopilot", s.autopilot);
    v("base_mode", s.base_mode);
    v("system_status", s.system_status);
    v("mavlink_version", s.mavlink_version);
  }
};

struct SystemTime {
  static constexpr uint32_t kId = 2;
  static constexpr uint8_t kCrcExtra = 137;
  static constexpr const char* kName = "SYSTEM_TIME";
  uint64_t time_unix_usec = 0;
  uint32_t time_boot_ms = 0;
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("time_unix_usec", s.time_unix_usec);
    v("time_boot_ms", s.time_boot_ms);
  }
};

struct GpsRawInt {
  static constexpr uint32_t kId = 24;
  static constexpr uint8_t kCrcExtra = 24;
  static constexpr const char* kName = "GPS_RAW_INT";
  uint64_t time_usec = 0;
  int32_t lat = 0;
  int32_t lon = 0;
  int32_t alt = 0;
  uint16_t eph = 0;
  uint16_t epv = 0;
  uint16_t vel = 0;
  uint16_t cog = 0;
  uint8_t fix_type = 0;
  uint8_t satellites_visible = 0;
  int32_t alt_ellipsoid = 0;
  uint32_t h_acc = 0;
  uint32_t v_acc = 0;
  uint32_t vel_acc = 0;
  uint32_t hdg_acc = 0;
  uint16_t yaw = 0;
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("time_usec", s.time_usec);
    v("lat", s.lat);
    v("lon", s.lon);
    v("alt", s.alt);
    v("eph", s.eph);
    v("epv", s.epv);
    v("vel", s.vel);
    v("cog", s.cog);
    v("fix_type", s.fix_type);
    v("satellites_visible", s.satellites_visible);
    v.extensions();
    v("alt_ellipsoid", s.alt_ellipsoid);
    v("h_acc", s.h_acc);
    v("v_acc", s.v_acc);
    v("vel_acc", s.vel_acc);
    v("hdg_acc", s.hdg_acc);
    v("yaw", s.yaw);
  }
};

struct Attitude {
  static constexpr uint32_t kId = 30;
  static constexpr uint8_t kCrcExtra = 39;
  static constexpr const char* kName = "ATTITUDE";
  uint32_t time_boot_ms = 0;
  float roll = 0, pitch = 0, yaw = 0;
  float rollspeed = 0, pitchspeed = 0, yawspeed = 0;
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("time_boot_ms", s.time_boot_ms);
    v("roll", s.roll);
    v("pitch", s.pitch);
    v("yaw", s.yaw);
    v("rollspeed", s.rollspeed);
    v("pitchspeed", s.pitchspeed);
    v("yawspeed", s.yawspeed);
  }
};

struct AttitudeQuaternion {
  static constexpr uint32_t kId = 31;
  static constexpr uint8_t kCrcExtra = 246;
  static constexpr const char* kName = "ATTITUDE_QUATERNION";
  uint32_t time_boot_ms = 0;
  float q1 = 1, q2 = 0, q3 = 0, q4 = 0;  // w, x, y, z
  float rollspeed = 0, pitchspeed = 0, yawspeed = 0;
  std::array<float, 4> repr_offset_q{};
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("time_boot_ms", s.time_boot_ms);
    v("q1", s.q1);
    v("q2", s.q2);
    v("q3", s.q3);
    v("q4", s.q4);
    v("rollspeed", s.rollspeed);
    v("pitchspeed", s.pitchspeed);
    v("yawspeed", s.yawspeed);
    v.extensions();
    v("repr_offset_q", s.repr_offset_q);
  }
};

struct GlobalPositionInt {
  static constexpr uint32_t kId = 33;
  static constexpr uint8_t kCrcExtra = 104;
  static constexpr const char* kName = "GLOBAL_POSITION_INT";
  uint32_t time_boot_ms = 0;
  int32_t lat = 0, lon = 0, alt = 0, relative_alt = 0;
  int16_t vx = 0, vy = 0, vz = 0;
  uint16_t hdg = 0;
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("time_boot_ms", s.time_boot_ms);
    v("lat", s.lat);
    v("lon", s.lon);
    v("alt", s.alt);
    v("relative_alt", s.relative_alt);
    v("vx", s.vx);
    v("vy", s.vy);
    v("vz", s.vz);
    v("hdg", s.hdg);
  }
};

struct VisionPositionEstimate {
  static constexpr uint32_t kId = 102;
  static constexpr uint8_t kCrcExtra = 158;
  static constexpr const char* kName = "VISION_POSITION_ESTIMATE";
  uint64_t usec = 0;
  float x = 0, y = 0, z = 0, roll = 0, pitch = 0, yaw = 0;
  std::array<float, 21> covariance{};
  uint8_t reset_counter = 0;
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("usec", s.usec);
    v("x", s.x);
    v("y", s.y);
    v("z", s.z);
    v("roll", s.roll);
    v("pitch", s.pitch);
    v("yaw", s.yaw);
    v.extensions();
    v("covariance", s.covariance);
    v("reset_counter", s.reset_counter);
  }
};

struct TimeSync {
  static constexpr uint32_t kId = 111;
  static constexpr uint8_t kCrcExtra = 34;
  static constexpr const char* kName = "TIMESYNC";
  int64_t tc1 = 0;  // ns; 0 in a request
  int64_t ts1 = 0;  // ns
  uint8_t target_system = 0;
  uint8_t target_component = 0;
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("tc1", s.tc1);
    v("ts1", s.ts1);
    v.extensions();
    v("target_system", s.target_system);
    v("target_component", s.target_component);
  }
};

struct DistanceSensor {
  static constexpr uint32_t kId = 132;
  static constexpr uint8_t kCrcExtra = 85;
  static constexpr const char* kName = "DISTANCE_SENSOR";
  uint32_t time_boot_ms = 0;
  uint16_t min_distance = 0, max_distance = 0, current_distance = 0;  // cm
  uint8_t type = 0, id = 0, orientation = 0, covariance = 0;
  float horizontal_fov = 0, vertical_fov = 0;
  std::array<float, 4> quaternion{};
  uint8_t signal_quality = 0;  // %: 0 unknown, 1 invalid, 100 perfect
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("time_boot_ms", s.time_boot_ms);
    v("min_distance", s.min_distance);
    v("max_distance", s.max_distance);
    v("current_distance", s.current_distance);
    v("type", s.type);
    v("id", s.id);
    v("orientation", s.orientation);
    v("covariance", s.covariance);
    v.extensions();
    v("horizontal_fov", s.horizontal_fov);
    v("vertical_fov", s.vertical_fov);
    v("quaternion", s.quaternion);
    v("signal_quality", s.signal_quality);
  }
};

struct GpsInput {
  static constexpr uint32_t kId = 232;
  static constexpr uint8_t kCrcExtra = 151;
  static constexpr const char* kName = "GPS_INPUT";
  // GPS_INPUT_IGNORE_FLAGS
  static constexpr uint16_t kIgnoreAlt = 1, kIgnoreHdop = 2, kIgnoreVdop = 4, kIgnoreVelHoriz = 8,
                            kIgnoreVelVert = 16, kIgnoreSpeedAccuracy = 32, kIgnoreHorizontalAccuracy = 64,
                            kIgnoreVerticalAccuracy = 128;
  uint64_t time_usec = 0;
  uint32_t time_week_ms = 0;
  int32_t lat = 0, lon = 0;
  float alt = 0, hdop = 0, vdop = 0, vn = 0, ve = 0, vd = 0;
  float speed_accuracy = 0, horiz_accuracy = 0, vert_accuracy = 0;
  uint16_t ignore_flags = 0;
  uint16_t time_week = 0;
  uint8_t gps_id = 0, fix_type = 0, satellites_visible = 0;
  uint16_t yaw = 0;  // cdeg, 0 = not available
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("time_usec", s.time_usec);
    v("time_week_ms", s.time_week_ms);
    v("lat", s.lat);
    v("lon", s.lon);
    v("alt", s.alt);
    v("hdop", s.hdop);
    v("vdop", s.vdop);
    v("vn", s.vn);
    v("ve", s.ve);
    v("vd", s.vd);
    v("speed_accuracy", s.speed_accuracy);
    v("horiz_accuracy", s.horiz_accuracy);
    v("vert_accuracy", s.vert_accuracy);
    v("ignore_flags", s.ignore_flags);
    v("time_week", s.time_week);
    v("gps_id", s.gps_id);
    v("fix_type", s.fix_type);
    v("satellites_visible", s.satellites_visible);
    v.extensions();
    v("yaw", s.yaw);
  }
};

struct Odometry {
  static constexpr uint32_t kId = 331;
  static constexpr uint8_t kCrcExtra = 91;
  static constexpr const char* kName = "ODOMETRY";
  uint64_t time_usec = 0;
  float x = 0, y = 0, z = 0;
  std::array<float, 4> q{};  // w, x, y, z
  float vx = 0, vy = 0, vz = 0, rollspeed = 0, pitchspeed = 0, yawspeed = 0;
  std::array<float, 21> pose_covariance{};
  std::array<float, 21> velocity_covariance{};
  uint8_t frame_id = 0, child_frame_id = 0;
  uint8_t reset_counter = 0, estimator_type = 0;
  int8_t quality = 0;
  template <class S, class V>
  static void visit(S& s, V& v) {
    v("time_usec", s.time_usec);
    v("x", s.x);
    v("y", s.y);
    v("z", s.z);
    v("q", s.q);
    v("vx", s.vx);
    v("vy", s.vy);
    v("vz", s.vz);
    v("rollspeed", s.rollspeed);
    v("pitchspeed", s.pitchspeed);
    v("yawspeed", s.yawspeed);
    v("pose_covariance", s.pose_covariance);
    v("velocity_covariance", s.velocity_covariance);
    v("frame_id", s.frame_id);
    v("child_frame_id", s.child_frame_id);
    v.extensions();
    v("reset_counter", s.reset_counter);
    v("estimator_type", s.estimator_type);
    v("quality", s.quality);
  }
};

// Calls f(M{}) once for every message type above (tests and the registry).
template <class F>
void for_each_message_type(F&& f) {
  f(Heartbeat{});
  f(SystemTime{});
  f(GpsRawInt{});
  f(Attitude{});
  f(AttitudeQuaternion{});
  f(GlobalPositionInt{});
  f(VisionPositionEstimate{});
  f(TimeSync{});
  f(DistanceSensor{});
  f(GpsInput{});
  f(Odometry{});
}

}  // namespace nadir::mavlink
