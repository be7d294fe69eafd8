#include "processes/mavlink_bridge/bridge_options.h"

#include <cmath>
#include <vector>

#include "common/sensor_calibration.h"

#include "processes/mavlink_bridge/udp_link.h"

namespace nadir::mavlink_bridge {

SerialOptions LinkOptions::default_serial() {
  SerialOptions s;
  s.device = "/dev/ttyACM0";
  s.baud = 921600;
  s.stall_timeout_s = 5.0;
  return s;
}

const OptionsSchema<BridgeOptions>& BridgeOptions::schema() {
  using O = BridgeOptions;
  using L = LinkOptions;
  using I = InputOptions;
  using P = OutputOptions;
  using G = GpsInputOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("mavlink_bridge", "PX4 / ArduPilot over MAVLink 2: INS and ALTIMETER in, POSE out.");
    s.number("system_id", 1, 255, "", "our MAVLink system id (a companion shares the autopilot's)", &O::system_id)
        .number("component_id", 1, 255, "", "our MAVLink component id", &O::component_id)
        .choice<std::string>("link.kind",
                             {{"udp_server", "udp_server"}, {"udp_client", "udp_client"}, {"serial", "serial"}},
                             "transport", &O::link, &L::kind)
        .text("link.local", "udp: bind address host:port (port 0: any)", &O::link, &L::local)
        .text("link.remote", "udp_client: send to host:port", &O::link, &L::remote)
        .text("link.autopilot_address",
              "udp_server: the autopilot's host:port, the only sender heard and answered (empty: learnt from its "
              "valid frames)",
              &O::link, &L::autopilot_address)
        .include("link.serial", SerialOptions::schema(), &O::link, &L::serial)
        .choice<std::string>("input.attitude",
                             {{"attitude", "attitude"}, {"attitude_quaternion", "attitude_quaternion"}, {"none", "none"}},
                             "message that gives the INS attitude", &O::input, &I::attitude)
        .flag("input.distance_sensor", "DISTANCE_SENSOR facing down -> ALTIMETER", &O::input, &I::distance_sensor)
        .number("input.distance_sensor_id", -1, 255, "", "-1: any sensor facing down", &O::input,
                &I::distance_sensor_id)
        .number("input.distance_latency_ms", 0.0, 1000.0, "ms", "measurement before its time_boot_ms stamp",
                &O::input, &I::distance_latency_ms)
        .number("input.min_signal_quality", 0.0, 1.0, "", "below: VALID_LOW_SIGNAL", &O::input,
                &I::min_signal_quality)
        .flag("input.truth", "GLOBAL_POSITION_INT / GPS_RAW_INT -> truth_channel", &O::input, &I::truth)
        .text("input.truth_channel", "LCM channel of the autopilot's GPS", &O::input, &I::truth_channel)
        .number("input.autopilot_system_id", 0, 255, "", "0: any system but our own", &O::input,
                &I::autopilot_system_id)
        .include("input.clock_sync", ClockSyncOptions::schema(), &O::input, &I::clock_sync)
        .number("output.vision_position_estimate_hz", 0.0, 100.0, "Hz", "0: off; at most this rate", &O::output,
                &P::vision_position_estimate_hz)
        .number("output.odometry_hz", 0.0, 100.0, "Hz", "ODOMETRY rate (0: off)", &O::output, &P::odometry_hz)
        .number("output.gps_input_hz", 0.0, 20.0, "Hz", "GPS_INPUT rate (0: off)", &O::output, &P::gps_input_hz)
        .number("output.heartbeat_hz", 0.0, 10.0, "Hz", "HEARTBEAT rate", &O::output, &P::heartbeat_hz)
        .number("output.timesync_hz", 0.0, 50.0, "Hz", "TIMESYNC requests to the autopilot (clock samples)",
                &O::output, &P::timesync_hz)
        .number("output.attitude_variance_rad2", 0.0, 10.0, "rad^2", "roll/pitch variance reported", &O::output,
                &P::attitude_variance_rad2)
        .number("output.gps_input.origin_latitude_deg", -89.0, 89.0, "deg", "where POSE's NED origin is",
                &O::output, &P::gps_input, &G::origin_latitude_deg)
        .number("output.gps_input.origin_longitude_deg", -180.0, 180.0, "deg", "... its longitude", &O::output,
                &P::gps_input, &G::origin_longitude_deg)
        .number("output.gps_input.origin_altitude_m", -1000.0, 20000.0, "m", "... its altitude (AMSL)", &O::output,
                &P::gps_input, &G::origin_altitude_m)
        .number("output.gps_input.satellites_visible", 0, 255, "", "reported: ArduPilot checks a minimum",
                &O::output, &P::gps_input, &G::satellites_visible)
        .number("output.gps_input.hdop", 0.0, 100.0, "", "reported HDOP", &O::output, &P::gps_input, &G::hdop)
        .number("output.gps_input.vdop", 0.0, 100.0, "", "reported VDOP", &O::output, &P::gps_input, &G::vdop)
        .number("output.gps_input.speed_accuracy_m_s", 0.0, 100.0, "m/s", "reported speed accuracy", &O::output,
                &P::gps_input, &G::speed_accuracy_m_s)
        .rule("input.truth_channel", [](const O& o) { return !o.input.truth || !o.input.truth_channel.empty(); },
              "must name a channel when input.truth is on");
    return s;
  }();
  return schema;
}

BridgeOptions BridgeOptions::from_config(const Config& root) {
  BridgeOptions o;
  o.source = root.source();
  schema().read(root.section_or_empty("mavlink_bridge"), &o);

  const Config shared = root.section_or_empty("altimeter");
  shared.require_known_keys(SensorCalibration::altimeter_keys());
  if (shared.has("beam_body")) {
    const std::vector<double> v = shared.get<std::vector<double>>("beam_body");
    if (v.size() != 3) throw shared.error("beam_body", "must have 3 numbers, has " + std::to_string(v.size()));
    o.input.beam_body = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  const double norm = o.input.beam_body.norm();
  if (!(norm > 0.5 && norm < 2.0)) throw shared.error("beam_body", "must be a direction (norm near 1)");
  o.input.beam_body /= norm;
  o.Check();
  return o;
}

void BridgeOptions::Check() const {
  schema().check(*this, Config(YAML::Node(YAML::NodeType::Map), source, "mavlink_bridge"));
  if (link.kind != "serial") {
    std::string why;
    require_option(parse_udp_endpoint(link.local, nullptr, &why), source, "mavlink_bridge.link.local", why);
    if (link.kind == "udp_server" && !link.autopilot_address.empty()) {
      require_option(parse_udp_endpoint(link.autopilot_address, nullptr, &why), source,
                     "mavlink_bridge.link.autopilot_address", why);
    }
    if (link.kind == "udp_client") {
      require_option(parse_udp_endpoint(link.remote, nullptr, &why), source, "mavlink_bridge.link.remote", why);
    }
  }
}

}  // namespace nadir::mavlink_bridge
