#pragma once
// The whole main() of an LCM process that runs one Node live: options,
// config, LCM, CONFIG at start, STATUS at 1 Hz, clean stop on SIGINT/SIGTERM.
// Only main decides to exit; errors come back as a return code with a message.

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

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

// Publishes the CONFIG message of a process (name, source, YAML).
void publish_config(Bus& bus, const std::string& name, const Config& config, int64_t utime);

}  // namespace nadir
