// nadir_replay: deterministic lockstep replay of a log through estimator nodes.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <sstream>

#include "common/json_writer.h"
#include "common/progress.h"
#include "common/replay.h"
#include "tools/replay/node_catalog.h"

namespace {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  nadir::NodeRegistry registry;
  nadir::register_all_nodes(registry);
  std::string known;
  for (const auto& n : registry.names()) known += (known.empty() ? "" : ",") + n;

  CLI::App app{
      "Replays a log through the chosen nodes in one process, in lockstep: input events in file order, each "
      "delivered synchronously, everything published appended to the output log with the input's timestamp. "
      "Same input + same config => byte-identical output. The config is written into the output log (CONFIG).",
      "nadir_replay"};
  nadir::ReplayOptions options;
  // The map matcher runs only when named: it needs a map (map_matcher.orthophoto, .dem).
  std::string nodes;
  for (const auto& n : registry.names()) {
    if (n != "map_matcher") nodes += (nodes.empty() ? "" : ",") + n;
  }
  bool json = false;
  bool no_passthrough = false;
  app.add_option("--in", options.in_path, "input log")->required();
  app.add_option("--out", options.out_path, "output log")->required();
  app.add_option("--nodes", nodes, "comma-separated nodes to run (available: " + known + ")")
      ->capture_default_str();
  app.add_option("--config", options.config_path, "YAML config (default: <checkout>/config/default.yaml)");
  app.add_option("--config-overlay", options.overlays,
                 "YAML fragment merged into the config key by key, e.g. nadir_calibrate's output (repeatable; "
                 "before --set)");
  app.add_option("--set", options.overrides, "override a config value: section.key=value (repeatable)");
  app.add_flag("--no-passthrough", no_passthrough, "write only what the nodes publish, not the input events");
  app.add_flag("--json", json, "print a machine-readable summary, no progress bar");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  options.nodes = split_list(nodes);
  options.passthrough = !no_passthrough;
  options.progress = !json && nadir::stderr_is_terminal();
  try {
    const nadir::ReplaySummary s = nadir::run_replay(options, registry);
    if (!s.damage_report.empty()) std::fputs(s.damage_report.c_str(), stderr);
    const double speed = s.wall_seconds > 0 ? s.log_seconds / s.wall_seconds : 0.0;
    if (json) {
      nadir::JsonWriter j;
      j.begin_object().field("in", options.in_path).field("out", options.out_path);
      j.field("events_in", s.events_in).field("passed_through", s.passed_through);
      j.field("replaced_input", s.replaced_input).field("published", s.published);
      j.field("corrupt_records", s.corrupt_records).field("truncated", s.truncated);
      j.field("log_seconds", s.log_seconds).field("wall_seconds", s.wall_seconds).field("speed_x", speed);
      j.key("published_per_channel").begin_object();
      for (const auto& [ch, n] : s.published_per_channel) j.field(ch, n);
      j.end_object().end_object();
      std::printf("%s\n", j.str().c_str());
    } else {
      std::printf("replayed %lld events (%.1f s of log) in %.2f s = %.1fx real time; %lld corrupt record(s)\n",
                  static_cast<long long>(s.events_in), s.log_seconds, s.wall_seconds, speed,
                  static_cast<long long>(s.corrupt_records));
      for (const auto& [ch, n] : s.published_per_channel) std::printf("  published %-12s %lld\n", ch.c_str(),
                                                                       static_cast<long long>(n));
      std::printf("output: %s\n", options.out_path.c_str());
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_replay: error: %s\n", e.what());
    return 1;
  }
}
