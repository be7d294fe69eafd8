#include "common/process_main.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/paths.h"
#include "common/shutdown.h"
#include "common/time_base.h"
#include "nadir/config_t.hpp"

namespace nadir {

void publish_config(Bus& bus, const std::string& name, const Config& config, int64_t utime) {
  config_t msg{};
  msg.utime = utime;
  msg.name = name;
  msg.source = config.source();
  msg.yaml = config.dump();
  bus.publish(channels::kConfig, msg);
}

int run_node_process(int argc, char** argv, const NodeProcessSpec& spec) {
  CLI::App app{spec.summary, "nadir_" + spec.name};
  std::string config_path;
  std::string lcm_url;
  double status_period_s = 1.0;
  std::vector<std::string> overrides;
  app.add_option("--config", config_path, "YAML config file (default: <checkout>/config/default.yaml)");
  app.add_option("--lcm-url", lcm_url, "LCM URL (default: $LCM_DEFAULT_URL or udpm with TTL 0)");
  app.add_option("--status-period", status_period_s, "seconds between STATUS messages")->check(CLI::Range(0.1, 60.0));
  app.add_option("--set", overrides, "override a config value: section.key=value (repeatable)");
  if (spec.add_options) spec.add_options(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  const std::string program = "nadir_" + spec.name;
  try {
    if (config_path.empty()) config_path = default_config_path();
    Config config = Config::load_file(config_path);
    for (const auto& o : overrides) config.apply_override(o);
    if (spec.apply_options) spec.apply_options(config);
    LcmBusOptions bus_options;
    bus_options.url = lcm_url;
    LcmBus bus(bus_options);
    std::unique_ptr<Node> node = spec.factory(config, bus);
    install_shutdown_handlers();

    std::fprintf(stderr, "%s: running on %s with %s\n", program.c_str(), bus.url().c_str(), config_path.c_str());
    const Config section = config.section_or_empty(spec.name);
    std::fprintf(stderr, "%s: options (%s):\n%s\n", program.c_str(), spec.name.c_str(), section.dump().c_str());
    publish_config(bus, spec.name, config, vehicle_time_now_us());

    const int64_t period_us = s_to_us(status_period_s);
    int64_t next_status_us = monotonic_now_us();
    auto send_status = [&](int8_t forced_state) {
      StatusReport report = node->status();
      if (forced_state >= 0) report.state = forced_state;
      bus.publish(channels::kStatus, bus.status_message(spec.name, report));
    };
    while (!shutdown_requested()) {
      if (bus.handle(50) < 0) {
        // A signal interrupts the wait (EINTR): that is a stop, not a failure.
        if (shutdown_requested() || errno == EINTR) continue;
        std::fprintf(stderr, "%s: LCM receive failed on %s\n", program.c_str(), bus.url().c_str());
        return 1;
      }
      const int64_t now = monotonic_now_us();
      if (now >= next_status_us) {
        node->on_tick(vehicle_time_now_us());
        send_status(-1);
        next_status_us = now + period_us;
      }
    }
    send_status(status_t::STATE_STOPPING);
    std::fprintf(stderr, "%s: stopped\n", program.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(), e.what());
    return 2;
  }
}

}  // namespace nadir
