#pragma once
// Options of nadir_mavlink_bridge, read from the `mavlink_bridge:` section
// (and the shared `altimeter.beam_body`) of the config. Check() throws
// ConfigError naming the key and the allowed values.

#include <Eigen/Core>

#include <string>

#include "common/clock_sync.h"
#include "common/config.h"
#include "common/serial_port.h"

namespace nadir::mavlink_bridge {

struct LinkOptions {
  std::string kind = "udp_server";  // udp_server | udp_client | serial
  // udp_server: bind here, answer whoever sent last. udp_client: bind here
  // (port 0: any) and send to `remote`.
  std::string local = "127.0.0.1:14540";  // loopback unless configured: nothing listens outside by default
  std::string remote = "127.0.0.1:14580";
  // udp_server: the autopilot's address ("a.b.c.d:port"): answer only there
  // and drop datagrams from anyone else. Empty: the address the autopilot's
  // valid frames come from.
  std::string autopilot_address;
  SerialOptions serial = default_serial();  // kind serial: termios settings as the INS bridge's
  static SerialOptions default_serial();     // /dev/ttyACM0 at 921600, 5 s stall timeout
};

struct InputOptions {
  std::string attitude = "attitude";  // attitude | attitude_quaternion | none
  bool distance_sensor = true;        // DISTANCE_SENSOR facing down -> ALTIMETER
  int distance_sensor_id = -1;        // -1: any sensor facing down
  double distance_latency_ms = 0.0;   // measurement before its time_boot_ms stamp
  double min_signal_quality = 0.0;    // 0..1; below: VALID_LOW_SIGNAL
  bool truth = true;                  // GLOBAL_POSITION_INT / GPS_RAW_INT -> truth_channel
  std::string truth_channel = "AUTOPILOT_GPS";
  int autopilot_system_id = 0;        // 0: any system but our own
  ClockSyncOptions clock_sync;
  Eigen::Vector3d beam_body = Eigen::Vector3d::UnitZ();
};

struct GpsInputOptions {
  double origin_latitude_deg = 0.0;   // where POSE's NED origin is
  double origin_longitude_deg = 0.0;
  double origin_altitude_m = 0.0;     // AMSL
  int satellites_visible = 10;        // reported: ArduPilot checks a minimum
  double hdop = 1.0;
  double vdop = 1.0;
  double speed_accuracy_m_s = 0.5;    // POSE has no velocity covariance
};

struct OutputOptions {
  double vision_position_estimate_hz = 30.0;  // 0: off; at most this rate (POSE arrives at the frame rate)
  double odometry_hz = 0.0;
  double gps_input_hz = 0.0;
  double heartbeat_hz = 1.0;
  double timesync_hz = 10.0;                 // TIMESYNC requests to the autopilot (clock samples)
  double attitude_variance_rad2 = 3.0e-4;    // roll/pitch variance reported (from the INS: not estimated)
  GpsInputOptions gps_input;
};

struct BridgeOptions {
  LinkOptions link;
  int system_id = 1;      // a companion computer shares the autopilot's system id
  int component_id = 197; // MAV_COMP_ID_VISUAL_INERTIAL_ODOMETRY
  InputOptions input;
  OutputOptions output;
  std::string source = "<defaults>";

  // `root` is the whole config (mavlink_bridge: and altimeter: sections).
  static BridgeOptions from_config(const Config& root);
  static const OptionsSchema<BridgeOptions>& schema();  // every key of `mavlink_bridge:`
  void Check() const;
};

}  // namespace nadir::mavlink_bridge
