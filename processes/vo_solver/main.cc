// nadir_vo_solver: the paper's Algorithm 1 (and its comparison variants) as a
// live LCM process. TRACKS + INS + ALTIMETER in, VO_DELTA out.

#include "common/process_main.h"
#include "processes/vo_solver/vo_solver_node.h"

int main(int argc, char** argv) {
  nadir::NodeProcessSpec spec;
  spec.name = "vo_solver";
  spec.summary =
      "INS-assisted monocular VO solver (Zhang & Singh, Algorithm 1). Subscribes TRACKS, INS and ALTIMETER, "
      "synchronises them by sensor time and publishes VO_DELTA: the translation between frames in the level "
      "frame of the previous frame, heading change, ground tilt, covariance and a quality flag. "
      "Options: vo_solver section of the config (variant: feature_depth, the shipped default | paper | "
      "level_ground | homography | flow).";
  spec.factory = nadir::make_vo_solver_node;
  return nadir::run_node_process(argc, argv, spec);
}
