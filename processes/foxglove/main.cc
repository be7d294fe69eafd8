// nadir_foxglove: serves the LCM bus to Foxglove (WebSocket protocol
// foxglove.websocket.v1); see docs/foxglove.md.

#include "common/process_main.h"
#include "processes/foxglove/foxglove_node.h"

int main(int argc, char** argv) {
  nadir::NodeProcessSpec spec;
  spec.name = "foxglove";
  spec.summary =
      "Foxglove bridge: serves the LCM bus (a live set, or a log played by lcm-logplayer) over the Foxglove WebSocket "
      "protocol (foxglove.websocket.v1) on loopback, port 8765 by default: POSE and GROUND_TRUTH as "
      "foxglove.LocationFix (Map), PoseInFrame and FrameTransform (3D), CAMERA_IMAGE as foxglove.RawImage "
      "(decimated), TRACKS as foxglove.ImageAnnotations, VO_DELTA, STATUS, INS, ALTIMETER as plain JSON. Open "
      "Foxglove, 'Open connection', Foxglove WebSocket, ws://127.0.0.1:8765, and import "
      "config/foxglove/nadir_layout.json. Publishes only its STATUS. A lockstep replay is served by the foxglove "
      "node: nadir_replay --nodes tracker,vo_solver,yaw_fusion,foxglove. Options: the foxglove section of the config "
      "file (address, port, image_rate_hz, origin_*, client limits).";
  spec.factory = nadir::make_foxglove_node;
  return nadir::run_node_process(argc, argv, spec);
}
