#pragma once
// Small real nodes for testing the runtime before (and apart from) the
// estimator: they subscribe, keep state and publish, like the real ones.

#include <memory>

#include "common/bus.h"
#include "common/channels.h"
#include "common/node.h"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir::testing {

// Turns consecutive INS samples into a "delta" (yaw change, time step): a
// stand-in stage 1 with a config option (scale) so config reaches it.
class InsDeltaNode : public Node {
 public:
  InsDeltaNode(const Config& root, Bus& bus);
  std::string name() const override { return "ins_delta"; }
  std::vector<std::string> output_channels() const override { return {channels::kVoDelta}; }
  StatusReport status() const override { return report_; }

 private:
  void on_ins(const ins_t& msg);
  Bus& bus_;
  double scale_;
  bool have_prev_ = false;
  ins_t prev_{};
  StatusReport report_;
};

// Integrates the deltas into a pose: a stand-in stage 2.
class DeltaIntegratorNode : public Node {
 public:
  DeltaIntegratorNode(const Config& root, Bus& bus);
  std::string name() const override { return "delta_integrator"; }
  std::vector<std::string> output_channels() const override { return {channels::kPose}; }
  StatusReport status() const override { return report_; }

 private:
  void on_delta(const vo_delta_t& msg);
  Bus& bus_;
  pose_t pose_{};
  StatusReport report_;
};

void register_test_nodes(NodeRegistry& registry);

}  // namespace nadir::testing
