// nadir_yaw_fusion: fuses VO yaw increments with INS yaw and integrates the
// VO translations into POSE (see README.md).

#include "common/process_main.h"
#include "processes/yaw_fusion/yaw_fusion_node.h"

int main(int argc, char** argv) {
  nadir::NodeProcessSpec spec;
  spec.name = "yaw_fusion";
  spec.summary =
      "Yaw fusion: a Kalman filter predicts yaw with the VO yaw increment and updates it with the (gated) INS "
      "yaw; each VO translation is registered in the world with the fused yaw and integrated into POSE "
      "(local NED from the first frame, with covariance). Inputs VO_DELTA, INS, ALTIMETER; output POSE, "
      "STATUS, CONFIG. Options: the yaw_fusion section of the config file.";
  spec.factory = nadir::make_yaw_fusion_node;
  return nadir::run_node_process(argc, argv, spec);
}
