// nadir_map_matcher: absolute horizontal position fixes from registering
// camera frames against a reference map (orthophoto + DEM).

#include "common/process_main.h"
#include "processes/map_matcher/map_matcher_node.h"

int main(int argc, char** argv) {
  nadir::NodeProcessSpec spec;
  spec.name = "map_matcher";
  spec.summary =
      "Map matcher: registers one camera frame per map_matcher.interval_s against the reference map "
      "(map_matcher.orthophoto + map_matcher.dem) around the POSE of that frame and publishes accepted "
      "absolute fixes with their covariance on MAP_FIX; refusals (featureless, ambiguous, outside the map, ...) "
      "are counted in STATUS. Inputs CAMERA_IMAGE, POSE, INS (the start position only); output MAP_FIX, STATUS, "
      "CONFIG. Options: the map_matcher section of the config file (docs/maps.md).";
  spec.factory = [](const nadir::Config& root, nadir::Bus& bus) { return nadir::make_map_matcher_node(root, bus); };
  return nadir::run_node_process(argc, argv, spec);
}
