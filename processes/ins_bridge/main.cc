// nadir_ins_bridge: NovAtel SPAN INS and laser altimeter on two serial lines
// -> INS and ALTIMETER on LCM, on the vehicle time base.

#include <unistd.h>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "common/config.h"
#include "common/lcm_bus.h"
#include "common/paths.h"
#include "common/process_main.h"
#include "common/shutdown.h"
#include "common/time_base.h"
#include "processes/ins_bridge/bridge_runner.h"

int main(int argc, char** argv) {
  using namespace nadir;
  CLI::App app{
      "Reads a NovAtel SPAN INS (INSPVAA / INSPVASA / INSPVAB, INSSTDEVA/B, CRC-32 checked) and a laser "
      "altimeter (LightWare-style or number+unit lines) from two serial ports, maps GPS time onto the vehicle "
      "time base (CLOCK_REALTIME) with a minimum-delay clock estimator, and publishes INS and ALTIMETER. "
      "Serial settings, IMU-to-body rotation and range limits come from the ins_bridge: section of the config.",
      "nadir_ins_bridge"};
  std::string config_path;
  std::string lcm_url;
  std::string ins_device;
  std::string altimeter_device;
  double status_period_s = 1.0;
  app.add_option("--config", config_path, "YAML config file (default: <checkout>/config/default.yaml)");
  app.add_option("--lcm-url", lcm_url, "LCM URL (default: $LCM_DEFAULT_URL or udpm with TTL 0)");
  app.add_option("--ins-device", ins_device, "INS serial device (overrides ins_bridge.ins.device)");
  app.add_option("--altimeter-device", altimeter_device,
                 "altimeter serial device (overrides ins_bridge.altimeter.device)");
  app.add_option("--status-period", status_period_s, "seconds between STATUS messages")->check(CLI::Range(0.1, 60.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (config_path.empty()) config_path = default_config_path();
    const Config config = Config::load_file(config_path);
    ins_bridge::BridgeOptions options = ins_bridge::BridgeOptions::from_config(config);
    if (!ins_device.empty()) options.ins.serial.device = ins_device;
    if (!altimeter_device.empty()) options.altimeter.serial.device = altimeter_device;
    options.Check();

    LcmBusOptions bus_options;
    bus_options.url = lcm_url;
    LcmBus bus(bus_options);
    install_shutdown_handlers();
    std::fprintf(stderr, "nadir_ins_bridge: running on %s with %s\n", bus.url().c_str(), config_path.c_str());
    std::fprintf(stderr, "nadir_ins_bridge: INS %s @ %d, altimeter %s @ %d (%s)\n", options.ins.serial.device.c_str(),
                 options.ins.serial.baud, options.altimeter.serial.device.c_str(), options.altimeter.serial.baud,
                 options.altimeter.protocol.c_str());
    std::fprintf(stderr, "nadir_ins_bridge: options (ins_bridge):\n%s\n",
                 config.section_or_empty("ins_bridge").dump().c_str());
    publish_config(bus, "ins_bridge", config, vehicle_time_now_us());

    ins_bridge::BridgeRunner runner(options, bus, "ins_bridge", status_period_s);
    runner.run([] { return !shutdown_requested(); });
    const StatusReport last = runner.status();
    std::fprintf(stderr, "nadir_ins_bridge: stopped: published %lld, errors %lld\n",
                 static_cast<long long>(last.published), static_cast<long long>(last.errors));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_ins_bridge: error: %s\n", e.what());
    return 2;
  }
}
