#pragma once
// A process's logic: a class that knows only the Bus. main.cc runs it live on
// an LcmBus; nadir_replay runs several on one ReplayBus in lockstep.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/bus.h"
#include "common/config.h"
#include "common/status.h"

namespace nadir {

class Node {
 public:
  virtual ~Node() = default;
  virtual std::string name() const = 0;
  // Channels this node publishes on (replay drops them from its input).
  virtual std::vector<std::string> output_channels() const = 0;
  virtual StatusReport status() const = 0;
  // Called about once a second: wall time live, log time in replay. Nodes
  // must not let it change their estimates (replay must equal live).
  virtual void on_tick(int64_t now_utime) { (void)now_utime; }
};

// Builds a node from the whole config file (the node reads its own section).
using NodeFactory = std::function<std::unique_ptr<Node>(const Config& root, Bus& bus)>;

class NodeRegistry {
 public:
  void add(const std::string& name, NodeFactory factory);
  const NodeFactory* find(const std::string& name) const;
  std::vector<std::string> names() const;

 private:
  std::map<std::string, NodeFactory> factories_;
};

}  // namespace nadir
