// nadir_composed: tracker, vo_solver and yaw_fusion live in one process.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <sstream>

#include "common/process_main.h"
#include "tools/compose/compose.h"

int main(int argc, char** argv) {
  CLI::App app{
      "Runs estimator nodes (the same Node classes as nadir_tracker, nadir_vo_solver, nadir_yaw_fusion) live in "
      "one process: what one node publishes reaches the next in the same thread with no process hop, and every "
      "channel still goes out on LCM for lcm-logger and lcm-spy. Inputs (CAMERA_IMAGE, INS, ALTIMETER) come from "
      "LCM. Each node publishes its own CONFIG and STATUS. Separate processes stay the default; this is the "
      "low-latency option (launch_scripts/sets/sim_composed).",
      "nadir_composed"};
  nadir::ProcessCommandLine command_line;
  command_line.add_to(app);
  nadir::ComposeOptions options;
  std::string nodes = "tracker,vo_solver,yaw_fusion";
  app.add_option("--nodes", nodes, "comma-separated nodes to run in this process")->capture_default_str();
  app.add_option("--checkpoint", options.yaw_fusion_checkpoint,
                 "yaw_fusion's POSE checkpoint file (as nadir_yaw_fusion --checkpoint)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  options.nodes.clear();
  std::stringstream in(nodes);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) options.nodes.push_back(item);
  }
  try {
    const nadir::Config config = command_line.load_config();
    nadir::LcmBusOptions bus_options;
    bus_options.url = command_line.lcm_url;
    nadir::LcmBus lcm(bus_options);
    nadir::Composition composition(options, config, lcm);
    return nadir::run_live_nodes("nadir_composed", lcm, config, composition.live_nodes(), command_line.status_period_s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_composed: error: %s\n", e.what());
    return 2;
  }
}
