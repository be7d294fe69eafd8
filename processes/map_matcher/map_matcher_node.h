#pragma once
// The map matcher process: CAMERA_IMAGE + POSE + INS in, MAP_FIX out.
//
// At most one frame per interval_s of sensor time is kept as a candidate;
// when the POSE of that frame comes (same utime; or at once when it came
// first, as in a lockstep replay), the frame is matched with that pose as the
// prior (map_matcher.h) and an accepted fix is published on MAP_FIX. A candidate whose POSE has not come within max_frame_age_s is
// dropped. Where the local frame of POSE lies on the Earth: the INS position
// at the first POSE's sensor time (the GNSS-aided solution at the start; common/pose_origin.h); no
// later INS position is used. Refusals are counted per reason in STATUS,
// the last one named in its detail.

#include <memory>

#include "common/bus.h"
#include "common/config.h"
#include "common/node.h"

namespace nadir {

// Throws ConfigError (options, no map given) or map::MapError (a map that cannot be used), naming the key or file.
std::unique_ptr<Node> make_map_matcher_node(const Config& root, Bus& bus);
void register_map_matcher_node(NodeRegistry& registry);

}  // namespace nadir
