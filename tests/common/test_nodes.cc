#include "tests/common/test_nodes.h"

#include <cmath>

namespace nadir::testing {

InsDeltaNode::InsDeltaNode(const Config& root, Bus& bus) : bus_(bus) {
  scale_ = root.section_or_empty("ins_delta").get_in_range<double>("scale", 1.0, 0.0, 100.0);
  bus_.subscribe<ins_t>(channels::kIns, [this](const ins_t& msg) { on_ins(msg); });
}

void InsDeltaNode::on_ins(const ins_t& msg) {
  ++report_.received;
  if (have_prev_) {
    vo_delta_t delta{};
    delta.utime = msg.utime;
    delta.prev_utime = prev_.utime;
    delta.dx = scale_ * msg.velocity_ned[0] * 1e-6 * static_cast<double>(msg.utime - prev_.utime);
    delta.dy = scale_ * msg.velocity_ned[1] * 1e-6 * static_cast<double>(msg.utime - prev_.utime);
    delta.dyaw = msg.yaw - prev_.yaw;
    delta.variant = "test";
    bus_.publish(channels::kVoDelta, delta);
    ++report_.published;
  }
  prev_ = msg;
  have_prev_ = true;
}

DeltaIntegratorNode::DeltaIntegratorNode(const Config&, Bus& bus) : bus_(bus) {
  bus_.subscribe<vo_delta_t>(channels::kVoDelta, [this](const vo_delta_t& msg) { on_delta(msg); });
}

void DeltaIntegratorNode::on_delta(const vo_delta_t& msg) {
  ++report_.received;
  pose_.utime = msg.utime;
  pose_.position_ned[0] += msg.dx;
  pose_.position_ned[1] += msg.dy;
  pose_.yaw += msg.dyaw;
  ++pose_.frames;
  bus_.publish(channels::kPose, pose_);
  ++report_.published;
}

void register_test_nodes(NodeRegistry& registry) {
  registry.add("ins_delta", [](const Config& c, Bus& b) { return std::make_unique<InsDeltaNode>(c, b); });
  registry.add("delta_integrator",
               [](const Config& c, Bus& b) { return std::make_unique<DeltaIntegratorNode>(c, b); });
}

}  // namespace nadir::testing
