#pragma once
// The whole main() of an LCM process that runs one Node live: options,
// config, LCM, CONFIG at start, STATUS at 1 Hz, clean stop on SIGINT/SIGTERM.
// Only main decides to exit; errors come back as a return code with a message.
// run_live_nodes() is the loop itself, shared with nadir_composed (several
// nodes in one process).

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "common/lcm_bus.h"
#include "common/node.h"

namespace nadir {

struct NodeProcessSpec {
  std::string name;     // process name, e.g. "tracker" (binary nadir_tracker)
  std::string summary;  // one paragraph for --help
  NodeFactory factory;
  // Optional process-specific command-line options, applied to the config
  // before the node is built.
  std::function<void(CLI::App& app)> add_options;
  std::function<void(Config& config)> apply_options;
};

int run_node_process(int argc, char** argv, const NodeProcessSpec& spec);

// The options every live process takes: --config, --lcm-url, --status-period, --set.
struct ProcessCommandLine {
  std::string config_path;  // empty: default_config_path()
  std::string lcm_url;
  double status_period_s = 1.0;
  std::vector<std::string> overrides;
  void add_to(CLI::App& app);
  Config load_config();  // fills config_path; throws ConfigError naming the file/key
};

// A node running live, with what its STATUS reports: the bus it subscribed
// and published on (decode and handler errors) and its publish latencies.
struct LiveNode {
  Node* node;
  const Bus* bus;
  LatencyWindow* latency;
};

// Publishes each node's CONFIG, then handles LCM until SIGINT/SIGTERM with
// every node's STATUS each period (and a last one, STOPPING). Returns the
// process's exit code.
int run_live_nodes(const std::string& program, LcmBus& lcm, const Config& config, const std::vector<LiveNode>& nodes,
                   double status_period_s);

// Publishes the CONFIG message of a process (name, source, YAML).
void publish_config(Bus& bus, const std::string& name, const Config& config, int64_t utime);

}  // namespace nadir
