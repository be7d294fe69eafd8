// nadir_mavlink_bridge: PX4 / ArduPilot over MAVLink (UDP or serial) ->
// INS, ALTIMETER (and truth) on LCM; POSE on LCM -> VISION_POSITION_ESTIMATE,
// ODOMETRY, GPS_INPUT to the autopilot, as a companion computer.

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "common/config.h"
#include "common/lcm_bus.h"
#include "common/paths.h"
#include "common/process_main.h"
#include "common/shutdown.h"
#include "common/time_base.h"
#include "processes/mavlink_bridge/bridge_runner.h"

int main(int argc, char** argv) {
  using namespace nadir;
  CLI::App app{
      "Talks MAVLink 2 (v1 accepted on input) to a PX4 or ArduPilot autopilot over UDP or a serial port. In: "
      "ATTITUDE or ATTITUDE_QUATERNION -> INS, DISTANCE_SENSOR facing down -> ALTIMETER, GLOBAL_POSITION_INT / "
      "GPS_RAW_INT -> a truth channel; the autopilot's boot time is mapped onto the vehicle time base from "
      "SYSTEM_TIME and TIMESYNC with the minimum-delay clock estimator. Out: POSE -> VISION_POSITION_ESTIMATE, "
      "ODOMETRY and/or GPS_INPUT at configured rates, HEARTBEAT as a companion computer. Link, rates and the "
      "GPS_INPUT origin come from the mavlink_bridge: section of the config.",
      "nadir_mavlink_bridge"};
  std::string config_path;
  std::string lcm_url;
  std::string link_kind;
  std::string local;
  std::string remote;
  std::string autopilot;
  std::string device;
  std::vector<std::string> overrides;
  double status_period_s = 1.0;
  app.add_option("--config", config_path, "YAML config file (default: <checkout>/config/default.yaml)");
  app.add_option("--lcm-url", lcm_url, "LCM URL (default: $LCM_DEFAULT_URL or udpm with TTL 0)");
  app.add_option("--link", link_kind, "udp_server | udp_client | serial (overrides mavlink_bridge.link.kind)");
  app.add_option("--local", local, "UDP ADDRESS:PORT to bind (overrides mavlink_bridge.link.local)");
  app.add_option("--remote", remote, "UDP ADDRESS:PORT to send to, udp_client (mavlink_bridge.link.remote)");
  app.add_option("--autopilot", autopilot,
                 "udp_server: the autopilot's ADDRESS:PORT, the only sender heard and answered "
                 "(mavlink_bridge.link.autopilot_address)");
  app.add_option("--device", device, "serial device (overrides mavlink_bridge.link.serial.device)");
  app.add_option("--set", overrides, "config override KEY=VALUE, e.g. mavlink_bridge.output.odometry_hz=30");
  app.add_option("--status-period", status_period_s, "seconds between STATUS messages")->check(CLI::Range(0.1, 60.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (config_path.empty()) config_path = default_config_path();
    Config config = Config::load_file(config_path);
    for (const std::string& o : overrides) config.apply_override(o);
    if (!link_kind.empty()) config.apply_override("mavlink_bridge.link.kind=" + link_kind);
    if (!local.empty()) config.apply_override("mavlink_bridge.link.local=" + local);
    if (!remote.empty()) config.apply_override("mavlink_bridge.link.remote=" + remote);
    if (!autopilot.empty()) config.apply_override("mavlink_bridge.link.autopilot_address=" + autopilot);
    if (!device.empty()) config.apply_override("mavlink_bridge.link.serial.device=" + device);
    const mavlink_bridge::BridgeOptions options = mavlink_bridge::BridgeOptions::from_config(config);

    LcmBusOptions bus_options;
    bus_options.url = lcm_url;
    LcmBus bus(bus_options);
    install_shutdown_handlers();
    mavlink_bridge::BridgeRunner runner(options, bus, "mavlink_bridge", status_period_s);
    std::fprintf(stderr, "nadir_mavlink_bridge: running on %s with %s; link %s %s\n", bus.url().c_str(),
                 config_path.c_str(), options.link.kind.c_str(),
                 options.link.kind == "serial" ? options.link.serial.device.c_str() : options.link.local.c_str());
    publish_config(bus, "mavlink_bridge", config, vehicle_time_now_us());
    runner.run([] { return !shutdown_requested(); });
    const StatusReport last = runner.status();
    std::fprintf(stderr, "nadir_mavlink_bridge: stopped: published %lld, frames rejected %lld\n",
                 static_cast<long long>(last.published), static_cast<long long>(runner.bridge().rejected_frames()));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_mavlink_bridge: error: %s\n", e.what());
    return 2;
  }
}
