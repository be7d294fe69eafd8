#include "common/node.h"

#include <stdexcept>

namespace nadir {

void NodeRegistry::add(const std::string& name, NodeFactory factory) {
  if (!factories_.emplace(name, std::move(factory)).second) {
    throw std::invalid_argument("node '" + name + "' is registered twice");
  }
}

const NodeFactory* NodeRegistry::find(const std::string& name) const {
  const auto it = factories_.find(name);
  return it == factories_.end() ? nullptr : &it->second;
}

std::vector<std::string> NodeRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& entry : factories_) out.push_back(entry.first);
  return out;
}

}  // namespace nadir
