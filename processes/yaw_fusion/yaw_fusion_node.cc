#include "processes/yaw_fusion/yaw_fusion_node.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/channels.h"
#include "common/geometry.h"
#include "common/input_checks.h"
#include "processes/yaw_fusion/checkpoint.h"
#include "processes/yaw_fusion/yaw_fusion_estimator.h"

namespace nadir {

namespace {

class YawFusionNode : public Node {
 public:
  YawFusionNode(const YawFusionOptions& options, const InputCheckOptions& checks, Bus& bus,
                const std::string& checkpoint_path)
      : bus_(bus), estimator_(options), gate_(checks) {
    if (!checkpoint_path.empty()) {
      checkpoint_ = std::make_unique<PoseCheckpoint>(checkpoint_path);
      const std::optional<yaw_fusion_checkpoint_t> last = checkpoint_->load(&checkpoint_problem_);
      if (last) estimator_.resume_from(*last);
    }
    bus_.subscribe<vo_delta_t>(channels::kVoDelta, [this](const vo_delta_t& msg) {
      if (gate_.admit(channels::kVoDelta, msg)) publish(estimator_.add_vo_delta(msg));
    });
    bus_.subscribe<ins_t>(channels::kIns, [this](const ins_t& msg) {
      if (gate_.admit(channels::kIns, msg)) publish(estimator_.add_ins(msg));
    });
    bus_.subscribe<altimeter_t>(channels::kAltimeter, [this](const altimeter_t& msg) {
      if (gate_.admit(channels::kAltimeter, msg)) publish(estimator_.add_altimeter(msg));
    });
    bus_.subscribe<ground_points_t>(channels::kVoGround, [this](const ground_points_t& msg) {
      if (gate_.admit(channels::kVoGround, msg)) estimator_.add_ground_points(msg);
    });
    bus_.subscribe<map_fix_t>(channels::kMapFix, [this](const map_fix_t& msg) { estimator_.add_map_fix(msg); });
  }

  std::string name() const override { return "yaw_fusion"; }
  std::vector<std::string> output_channels() const override { return {channels::kPose}; }

  StatusReport status() const override {
    const YawFusionCounters& c = estimator_.counters();
    StatusReport report;
    report.received =
        c.vo_deltas_received + c.ins_received + c.altimeter_received + c.ground_frames_received + gate_.rejected();
    report.published = published_;
    report.dropped = c.vo_deltas_late + c.vo_deltas_duplicate;
    report.errors = c.vo_deltas_invalid + c.ins_invalid + c.time_jumps_dropped + c.map_fixes_invalid;
    if (!estimator_.started()) {
      report.state = status_t::STATE_STARTING;
      report.detail = "waiting for the first VO_DELTA with INS covering it";
    } else if (estimator_.vo_lost()) {
      report.state = status_t::STATE_WARN;
      report.detail = "no usable VO_DELTA for longer than gap.max_duration_s; gap poses stopped";
    } else if (!c.last_problem.empty() && report.errors > 0) {
      report.detail = c.last_problem;
    }
    const PoseFilter& f = estimator_.filter();
    report.counters = {
        {"vo_deltas_integrated", static_cast<double>(c.vo_deltas_integrated)},
        {"ground_frames_received", static_cast<double>(c.ground_frames_received)},
        {"coast_seen_ground_poses", static_cast<double>(c.coast_seen_ground_poses)},
        {"coasts_bridged", static_cast<double>(c.coasts_bridged)},
        {"vo_deltas_invalid", static_cast<double>(c.vo_deltas_invalid)},
        {"vo_deltas_quality_rejected", static_cast<double>(c.vo_deltas_quality_rejected)},
        {"vo_deltas_before_start", static_cast<double>(c.vo_deltas_before_start)},
        {"vo_deltas_duplicate", static_cast<double>(c.vo_deltas_duplicate)},
        {"vo_deltas_late", static_cast<double>(c.vo_deltas_late)},
        {"vo_deltas_without_ins", static_cast<double>(c.vo_deltas_without_ins)},
        {"vo_deltas_pending", static_cast<double>(estimator_.pending_deltas())},
        {"ins_invalid", static_cast<double>(c.ins_invalid)},
        {"ins_duplicate", static_cast<double>(c.ins_duplicate)},
        {"ins_yaw_updates", static_cast<double>(c.ins_yaw_updates)},
        {"ins_yaw_rejected", static_cast<double>(c.ins_yaw_rejected)},
        {"ins_yaw_unusable", static_cast<double>(c.ins_yaw_unusable)},
        {"yaw_reinitialised", static_cast<double>(c.yaw_reinitialised)},
        {"yaw_from_ins_in_gap", static_cast<double>(c.yaw_from_ins_in_gap)},
        {"altimeter_invalid", static_cast<double>(c.altimeter_invalid)},
        {"altimeter_rejected", static_cast<double>(c.altimeter_rejected)},
        {"altimeter_down_resets", static_cast<double>(c.altimeter_down_resets)},
        {"frames_without_altimeter", static_cast<double>(c.frames_without_altimeter)},
        {"time_jumps_dropped", static_cast<double>(c.time_jumps_dropped)},
        {"gap_bridges", static_cast<double>(c.gap_bridges)},
        {"gap_poses", static_cast<double>(c.gap_poses)},
        {"gap_poses_superseded", static_cast<double>(c.gap_poses_superseded)},
        {"yaw_stddev_deg", f.initialised() ? rad_to_deg(std::sqrt(f.yaw_variance())) : 0.0},
        {"position_stddev_h_m",
         f.initialised() ? std::sqrt(f.position_covariance()(0, 0) + f.position_covariance()(1, 1)) : 0.0},
    };
    report.counters.emplace_back("resumed_from_checkpoint", static_cast<double>(c.resumed));
    report.counters.emplace_back("vo_deltas_coasted", static_cast<double>(c.vo_deltas_coasted));
    report.counters.emplace_back("coast_episodes", static_cast<double>(c.coast_episodes));
    report.counters.emplace_back("coast_expired", static_cast<double>(c.coast_expired));
    report.counters.emplace_back("coast_ground_steps", static_cast<double>(c.coast_ground_steps));
    report.counters.emplace_back("deltas_reverted", static_cast<double>(c.deltas_reverted));
    report.counters.emplace_back("map_fixes_received", static_cast<double>(c.map_fixes_received));
    report.counters.emplace_back("map_fixes_applied", static_cast<double>(c.map_fixes_applied));
    report.counters.emplace_back("map_fixes_rejected", static_cast<double>(c.map_fixes_rejected));
    report.counters.emplace_back("map_fixes_invalid", static_cast<double>(c.map_fixes_invalid));
    report.counters.emplace_back("map_fixes_unmatched", static_cast<double>(c.map_fixes_unmatched));
    report.counters.emplace_back("map_fixes_late", static_cast<double>(c.map_fixes_late));
    report.counters.emplace_back("map_fixes_with_height", static_cast<double>(c.map_fixes_with_height));
    report.counters.emplace_back("map_fix_heights_rejected", static_cast<double>(c.map_fix_heights_rejected));
    // The INS heading bias the map fixes estimated (0 without fixes), and what is left of it.
    const Eigen::Matrix2d bias = f.yaw_bias_covariance();
    report.counters.emplace_back("heading_bias_estimate_deg", rad_to_deg(f.yaw_bias_estimate()));
    report.counters.emplace_back("heading_bias_stddev_deg", rad_to_deg(std::sqrt(std::max(0.0, bias.sum()))));
    for (int bit = 0; bit < kCoastReasons; ++bit) {
      report.counters.emplace_back(std::string("coast_") + coast_reason_name(bit),
                                   static_cast<double>(c.coast_reasons[bit]));
    }
    if (checkpoint_) {
      report.counters.emplace_back("checkpoint_saves", static_cast<double>(checkpoint_->saves()));
      report.counters.emplace_back("checkpoint_errors", static_cast<double>(checkpoint_->save_errors()));
      if (!checkpoint_->last_error().empty()) report.detail = checkpoint_->last_error();
      if (!checkpoint_problem_.empty()) report.detail = checkpoint_problem_;
    }
    gate_.add_counters(&report);
    gate_.warn_if_rejecting(&report);
    return report;
  }

 private:
  void publish(const std::vector<pose_t>& poses) {
    for (const pose_t& pose : poses) {
      bus_.publish(channels::kPose, pose);
      ++published_;
      if (checkpoint_) checkpoint_->save(estimator_.checkpoint(pose));
    }
  }

  Bus& bus_;
  YawFusionEstimator estimator_;
  InputGate gate_;
  std::unique_ptr<PoseCheckpoint> checkpoint_;  // live runs started with --checkpoint only
  std::string checkpoint_problem_;
  int64_t published_ = 0;
};

}  // namespace

std::unique_ptr<Node> make_yaw_fusion_node(const Config& root, Bus& bus) {
  return make_yaw_fusion_node_with_checkpoint(root, bus, "");
}

std::unique_ptr<Node> make_yaw_fusion_node_with_checkpoint(const Config& root, Bus& bus,
                                                           const std::string& checkpoint_path) {
  return std::make_unique<YawFusionNode>(YawFusionOptions::from_config(root), InputCheckOptions::from_config(root), bus,
                                         checkpoint_path);
}

void register_yaw_fusion_node(NodeRegistry& registry) { registry.add("yaw_fusion", make_yaw_fusion_node); }

}  // namespace nadir
