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

void ProcessCommandLine::add_to(CLI::App& app) {
  app.add_option("--config", config_path, "YAML config file (default: <checkout>/config/default.yaml)");
  app.add_option("--lcm-url", lcm_url, "LCM URL (default: $LCM_DEFAULT_URL or udpm with TTL 0)");
  app.add_option("--status-period", status_period_s, "seconds between STATUS messages")->check(CLI::Range(0.1, 60.0));
  app.add_option("--set", overrides, "override a config value: section.key=value (repeatable)");
}

Config ProcessCommandLine::load_config() {
  if (config_path.empty()) config_path = default_config_path();
  Config config = Config::load_file(config_path);
  for (const auto& o : overrides) config.apply_override(o);
  return config;
}

int run_live_nodes(const std::string& program, LcmBus& lcm, const Config& config, const std::vector<LiveNode>& nodes,
                   double status_period_s) {
  install_shutdown_handlers();
  for (const LiveNode& n : nodes) {
    std::fprintf(stderr, "%s: running %s on %s with %s\n", program.c_str(), n.node->name().c_str(), lcm.url().c_str(),
                 config.source().c_str());
    const Config section = config.section_or_empty(n.node->name());
    std::fprintf(stderr, "%s: options (%s):\n%s\n", program.c_str(), n.node->name().c_str(), section.dump().c_str());
    publish_config(lcm, n.node->name(), config, vehicle_time_now_us());
  }
  const int64_t period_us = s_to_us(status_period_s);
  int64_t next_status_us = monotonic_now_us();
  auto send_status = [&](int8_t forced_state) {
    for (size_t i = 0; i < nodes.size(); ++i) {
      const LiveNode& n = nodes[i];
      StatusReport report = n.node->status();
      if (forced_state >= 0) report.state = forced_state;
      status_t msg = make_status_message(n.node->name(), static_cast<int32_t>(getpid()), vehicle_time_now_us(), report,
                                         n.bus->error_counts());
      n.latency->take(&msg.latency_p50_ms, &msg.latency_p99_ms, &msg.latency_max_ms);
      // The LCM socket is the process's: its per-channel counts and kernel
      // drops go with the first node's STATUS only, or a capture check would
      // count a composed process's channels once per node.
      if (i == 0) lcm.add_transport_counters(&msg);
      lcm.publish(channels::kStatus, msg);
    }
  };
  while (!shutdown_requested()) {
    if (lcm.handle(50) < 0) {
      // A signal interrupts the wait (EINTR): that is a stop, not a failure.
      if (shutdown_requested() || errno == EINTR) continue;
      std::fprintf(stderr, "%s: LCM receive failed on %s\n", program.c_str(), lcm.url().c_str());
      return 1;
    }
    const int64_t now = monotonic_now_us();
    if (now >= next_status_us) {
      for (const LiveNode& n : nodes) n.node->on_tick(vehicle_time_now_us());
      send_status(-1);
      next_status_us = now + period_us;
    }
  }
  send_status(status_t::STATE_STOPPING);
  std::fprintf(stderr, "%s: stopped\n", program.c_str());
  return 0;
}

int run_node_process(int argc, char** argv, const NodeProcessSpec& spec) {
  CLI::App app{spec.summary, "nadir_" + spec.name};
  ProcessCommandLine command_line;
  command_line.add_to(app);
  if (spec.add_options) spec.add_options(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  const std::string program = "nadir_" + spec.name;
  try {
    Config config = command_line.load_config();
    if (spec.apply_options) spec.apply_options(config);
    LcmBusOptions bus_options;
    bus_options.url = command_line.lcm_url;
    LcmBus bus(bus_options);
    std::unique_ptr<Node> node = spec.factory(config, bus);
    return run_live_nodes(program, bus, config, {LiveNode{node.get(), &bus, &bus.latency()}},
                          command_line.status_period_s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(), e.what());
    return 2;
  }
}

}  // namespace nadir
