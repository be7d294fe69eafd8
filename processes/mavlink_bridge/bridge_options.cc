#include "processes/mavlink_bridge/bridge_options.h"

#include <cmath>
#include <vector>

#include "processes/mavlink_bridge/udp_link.h"

namespace nadir::mavlink_bridge {
namespace {

double rate(const Config& section, const std::string& key, double fallback, double max_hz) {
  return section.get_in_range<double>(key, fallback, 0.0, max_hz);
}

}  // namespace

BridgeOptions BridgeOptions::from_config(const Config& root) {
  BridgeOptions o;
  o.source = root.source();
  const Config s = root.section_or_empty("mavlink_bridge");
  o.system_id = s.get_in_range<int>("system_id", o.system_id, 1, 255);
  o.component_id = s.get_in_range<int>("component_id", o.component_id, 1, 255);

  const Config link = s.section_or_empty("link");
  o.link.kind = link.get<std::string>("kind", o.link.kind);
  o.link.local = link.get<std::string>("local", o.link.local);
  o.link.remote = link.get<std::string>("remote", o.link.remote);
  SerialOptions serial_defaults;
  serial_defaults.device = "/dev/ttyACM0";
  serial_defaults.baud = 921600;
  serial_defaults.stall_timeout_s = 5.0;
  o.link.serial = SerialOptions::from_config(link.section_or_empty("serial"), serial_defaults);

  const Config in = s.section_or_empty("input");
  o.input.attitude = in.get<std::string>("attitude", o.input.attitude);
  o.input.distance_sensor = in.get<bool>("distance_sensor", o.input.distance_sensor);
  o.input.distance_sensor_id = in.get_in_range<int>("distance_sensor_id", o.input.distance_sensor_id, -1, 255);
  o.input.distance_latency_ms = in.get_in_range<double>("distance_latency_ms", o.input.distance_latency_ms, 0, 1000);
  o.input.min_signal_quality = in.get_in_range<double>("min_signal_quality", o.input.min_signal_quality, 0, 1);
  o.input.truth = in.get<bool>("truth", o.input.truth);
  o.input.truth_channel = in.get<std::string>("truth_channel", o.input.truth_channel);
  o.input.autopilot_system_id = in.get_in_range<int>("autopilot_system_id", o.input.autopilot_system_id, 0, 255);
  o.input.clock_sync = ClockSyncOptions::from_config(in.section_or_empty("clock_sync"), o.input.clock_sync);

  const Config out = s.section_or_empty("output");
  o.output.vision_position_estimate_hz =
      rate(out, "vision_position_estimate_hz", o.output.vision_position_estimate_hz, 100.0);
  o.output.odometry_hz = rate(out, "odometry_hz", o.output.odometry_hz, 100.0);
  o.output.gps_input_hz = rate(out, "gps_input_hz", o.output.gps_input_hz, 20.0);
  o.output.heartbeat_hz = rate(out, "heartbeat_hz", o.output.heartbeat_hz, 10.0);
  o.output.timesync_hz = rate(out, "timesync_hz", o.output.timesync_hz, 50.0);
  o.output.attitude_variance_rad2 =
      out.get_in_range<double>("attitude_variance_rad2", o.output.attitude_variance_rad2, 0.0, 10.0);
  const Config gps = out.section_or_empty("gps_input");
  GpsInputOptions& g = o.output.gps_input;
  g.origin_latitude_deg = gps.get_in_range<double>("origin_latitude_deg", g.origin_latitude_deg, -89.0, 89.0);
  g.origin_longitude_deg = gps.get_in_range<double>("origin_longitude_deg", g.origin_longitude_deg, -180.0, 180.0);
  g.origin_altitude_m = gps.get_in_range<double>("origin_altitude_m", g.origin_altitude_m, -1000.0, 20000.0);
  g.satellites_visible = gps.get_in_range<int>("satellites_visible", g.satellites_visible, 0, 255);
  g.hdop = gps.get_in_range<double>("hdop", g.hdop, 0.0, 100.0);
  g.vdop = gps.get_in_range<double>("vdop", g.vdop, 0.0, 100.0);
  g.speed_accuracy_m_s = gps.get_in_range<double>("speed_accuracy_m_s", g.speed_accuracy_m_s, 0.0, 100.0);

  const Config shared = root.section_or_empty("altimeter");
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
  require_option(link.kind == "udp_server" || link.kind == "udp_client" || link.kind == "serial", source,
                 "mavlink_bridge.link.kind", "= '" + link.kind + "' must be udp_server, udp_client or serial");
  if (link.kind == "serial") {
    link.serial.Check(source, "mavlink_bridge.link.serial");
  } else {
    std::string why;
    require_option(parse_udp_endpoint(link.local, nullptr, &why), source, "mavlink_bridge.link.local", why);
    if (link.kind == "udp_client") {
      require_option(parse_udp_endpoint(link.remote, nullptr, &why), source, "mavlink_bridge.link.remote", why);
    }
  }
  require_option(input.attitude == "attitude" || input.attitude == "attitude_quaternion" || input.attitude == "none",
                 source, "mavlink_bridge.input.attitude",
                 "= '" + input.attitude + "' must be attitude, attitude_quaternion or none");
  require_option(!input.truth || !input.truth_channel.empty(), source, "mavlink_bridge.input.truth_channel",
                 "must name a channel when input.truth is on");
  try {
    input.clock_sync.Check();
  } catch (const ConfigError& e) {
    throw ConfigError(source + ": mavlink_bridge.input." + e.what());
  }
}

}  // namespace nadir::mavlink_bridge
