// nadir_tracker: Harris/KLT feature tracks from CAMERA_IMAGE to TRACKS.
#include "common/process_main.h"
#include "processes/tracker/tracker_node.h"

int main(int argc, char** argv) {
  nadir::NodeProcessSpec spec;
  spec.name = "tracker";
  spec.summary =
      "Tracks Harris corners (3x3 grid, per-cell replenishment) with pyramidal KLT and a forward-backward check "
      "from CAMERA_IMAGE to TRACKS (pixels and undistorted normalized coordinates, both frames' sensor times). "
      "Bad, out-of-order and wrongly sized images are flagged and counted in STATUS. Options: the 'tracker:' and "
      "'camera:' sections of the config.";
  spec.factory = nadir::make_tracker_node;
  return nadir::run_node_process(argc, argv, spec);
}
