// nadir_yaw_fusion: fuses VO yaw increments with INS yaw and integrates the
// VO translations into POSE (see README.md).

#include <string>

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
  // The checkpoint is a command-line option, not config: it is state of one
  // live run, and a replay (which reads the config) must never touch it.
  std::string checkpoint;
  spec.add_options = [&checkpoint](CLI::App& app) {
    app.add_option("--checkpoint", checkpoint,
                   "POSE checkpoint file: continue from it after a restart, rewrite it after every POSE");
  };
  spec.factory = [&checkpoint](const nadir::Config& root, nadir::Bus& bus) {
    return nadir::make_yaw_fusion_node_with_checkpoint(root, bus, checkpoint);
  };
  return nadir::run_node_process(argc, argv, spec);
}
