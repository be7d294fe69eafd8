#pragma once
// The yaw fusion process: VO_DELTA + INS + ALTIMETER in, POSE out
// (see yaw_fusion_estimator.h for the synchronisation and README.md for the filter).

#include <memory>
#include <string>

#include "common/bus.h"
#include "common/config.h"
#include "common/node.h"

namespace nadir {

std::unique_ptr<nadir::Node> make_yaw_fusion_node(const nadir::Config& root, nadir::Bus& bus);
// The same, continuing from the POSE checkpoint at `checkpoint_path` if there
// is one and writing it after every POSE (see checkpoint.h); "" = none.
std::unique_ptr<nadir::Node> make_yaw_fusion_node_with_checkpoint(const nadir::Config& root, nadir::Bus& bus,
                                                                  const std::string& checkpoint_path);
void register_yaw_fusion_node(nadir::NodeRegistry& registry);

}  // namespace nadir
