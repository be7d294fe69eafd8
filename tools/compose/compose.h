#pragma once
// Builds the chosen estimator nodes on one ComposedBus over LCM (nadir_composed).

#include <memory>
#include <string>
#include <vector>

#include "common/composed_bus.h"
#include "common/config.h"
#include "common/node.h"
#include "common/process_main.h"

namespace nadir {

struct ComposeOptions {
  std::vector<std::string> nodes{"tracker", "vo_solver", "yaw_fusion"};
  std::string yaw_fusion_checkpoint;  // as nadir_yaw_fusion --checkpoint; "" = none
  void Check() const;                 // throws std::invalid_argument naming the node
};

// The nodes of one process, each on its own NodePort of one ComposedBus.
class Composition {
 public:
  // Throws std::invalid_argument (unknown node) or ConfigError.
  Composition(const ComposeOptions& options, const Config& config, Bus& outside);

  std::vector<LiveNode> live_nodes();

 private:
  ComposedBus bus_;
  std::vector<std::unique_ptr<NodePort>> ports_;
  std::vector<std::unique_ptr<Node>> nodes_;
};

}  // namespace nadir
