#pragma once
// The nodes nadir_replay can run, by name.

#include "common/node.h"

namespace nadir {

// Registers every estimator node built into this tree.
void register_all_nodes(NodeRegistry& registry);

}  // namespace nadir
