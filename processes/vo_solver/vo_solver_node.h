#pragma once
// The vo_solver process: TRACKS + INS + ALTIMETER in, VO_DELTA out.
// Inputs are buffered and synchronised by sensor time (FrameSync), frames are
// solved in utime order once their INS (and altimeter) inputs are final, so a
// live run and a lockstep replay give the same VO_DELTA.

#include <map>
#include <memory>

#include "common/bus.h"
#include "common/config.h"
#include "common/input_checks.h"
#include "common/node.h"
#include "common/vo_quality.h"
#include "nadir/ground_points_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/vo_delta_t.hpp"
#include "processes/vo_solver/feature_depth_map.h"
#include "processes/vo_solver/frame_sync.h"
#include "processes/vo_solver/range_at_frame.h"
#include "processes/vo_solver/vo_solver_options.h"

namespace nadir {

class VoSolverNode : public Node {
 public:
  static constexpr int kQualityBits = kVoQualityBits;  // vo_delta_t::QUALITY_* bits, counted in status
  // `checks`: the plausibility limits applied to every input before it
  // reaches the frame synchronisation (common/input_checks.h).
  VoSolverNode(const VoSolverOptions& options, Bus& bus, const InputCheckOptions& checks = InputCheckOptions());

  std::string name() const override { return "vo_solver"; }
  std::vector<std::string> output_channels() const override;
  StatusReport status() const override;

  void on_tracks(const tracks_t& tracks);
  void on_ins(const ins_t& ins);
  void on_altimeter(const altimeter_t& altimeter);

 private:
  void process_ready();
  // Also leaves the frame's trusted ground points in ground_ (feature_depth).
  vo_delta_t solve_frame(const tracks_t& tracks, bool flush);
  // VO_GROUND of the same frame first (when it has points), then VO_DELTA.
  void publish(const vo_delta_t& delta);
  void fill_ground_points(const vo::FramePair& pair, int64_t utime);

  VoSolverOptions options_;
  Bus& bus_;
  vo::FrameSync sync_;
  vo::FeatureDepthMap depth_map_;  // feature_depth variant: per-track depths
  ground_points_t ground_{};       // the last solved frame's trusted points (VO_GROUND)
  int64_t ground_published_ = 0;
  vo::LevelVelocity velocity_{0.5};  // moves a range sampled before its frame (range_at_frame.h)
  struct FrameRange {
    int64_t utime = INT64_MIN;
    double range_m = 0;
    Eigen::Vector3d beam_body = Eigen::Vector3d::UnitZ();
  };
  FrameRange curr_range_;  // the last pair's curr range as given to the solver (moved or not)
  InputGate gate_;
  std::map<int64_t, tracks_t> pending_;  // by utime
  int64_t last_published_utime_ = INT64_MIN;
  int64_t received_ = 0, published_ = 0, dropped_ = 0, errors_ = 0;
  int64_t flagged_ = 0, late_tracks_ = 0, duplicate_tracks_ = 0, bad_features_ = 0;
  int64_t quality_counts_[kQualityBits] = {};
  // feature_depth: pairs solved by the paper's model alone (too few own
  // depths, no anchor), and pairs that carried the scale without an anchor.
  int64_t paper_alone_pairs_ = 0, carried_scale_pairs_ = 0;
  int last_inliers_ = 0;
  double last_residual_px_ = 0;
  int last_quality_ = 0;
};

std::unique_ptr<Node> make_vo_solver_node(const Config& root, Bus& bus);
void register_vo_solver_node(NodeRegistry& registry);

}  // namespace nadir
