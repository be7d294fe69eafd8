#include "tools/compose/compose.h"

#include <set>
#include <stdexcept>

#include "processes/yaw_fusion/yaw_fusion_node.h"
#include "tools/replay/node_catalog.h"

namespace nadir {

void ComposeOptions::Check() const {
  if (nodes.empty()) throw std::invalid_argument("--nodes: name at least one node");
  std::set<std::string> seen;
  for (const auto& n : nodes) {
    if (!seen.insert(n).second) throw std::invalid_argument("--nodes: '" + n + "' is named twice");
  }
}

Composition::Composition(const ComposeOptions& options, const Config& config, Bus& outside) : bus_(outside) {
  options.Check();
  NodeRegistry registry;
  register_all_nodes(registry);
  std::set<std::string> produced;
  for (const auto& name : options.nodes) {
    const NodeFactory* factory = registry.find(name);
    if (factory == nullptr) {
      std::string known;
      for (const auto& n : registry.names()) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("--nodes: unknown node '" + name + "' (known: " + known + ")");
    }
    ports_.push_back(std::make_unique<NodePort>(bus_));
    if (name == "yaw_fusion") {
      nodes_.push_back(make_yaw_fusion_node_with_checkpoint(config, *ports_.back(), options.yaw_fusion_checkpoint));
    } else {
      nodes_.push_back((*factory)(config, *ports_.back()));
    }
    for (const auto& ch : nodes_.back()->output_channels()) produced.insert(ch);
  }
  bus_.connect_inputs(produced);
}

std::vector<LiveNode> Composition::live_nodes() {
  std::vector<LiveNode> out;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    out.push_back(LiveNode{nodes_[i].get(), ports_[i].get(), &ports_[i]->latency()});
  }
  return out;
}

}  // namespace nadir
