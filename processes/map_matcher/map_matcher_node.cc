#include "processes/map_matcher/map_matcher_node.h"

#include <array>
#include <cmath>
#include <deque>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/channels.h"
#include "common/input_checks.h"
#include "common/paths.h"
#include "common/pose_origin.h"
#include "common/sensor_calibration.h"
#include "nadir/ins_t.hpp"
#include "processes/map_matcher/map_matcher.h"

namespace nadir {

namespace {

std::string resolve(const std::string& path) {
  if (path.empty() || std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(checkout_root()) / path).string();
}

bool pose_finite(const pose_t& p) {
  double sum = p.roll + p.pitch + p.yaw + p.height_agl_m;
  for (int i = 0; i < 3; ++i) {
    sum += p.position_ned[i];
    for (int j = 0; j < 3; ++j) sum += p.position_covariance[i][j];
  }
  return std::isfinite(sum);
}

class MapMatcherNode : public Node {
 public:
  MapMatcherNode(const MapMatcherOptions& options, MapMatcher matcher, const InputCheckOptions& checks, Bus& bus)
      : options_(options), matcher_(std::move(matcher)), gate_(checks), bus_(bus) {
    bus_.subscribe<image_t>(channels::kCameraImage, [this](const image_t& msg) {
      if (gate_.admit(channels::kCameraImage, msg)) on_image(msg);
    });
    bus_.subscribe<ins_t>(channels::kIns, [this](const ins_t& msg) {
      if (!origin_ && gate_.admit(channels::kIns, msg)) {
        pose_origin_.add_ins(msg);
        take_origin();
      }
    });
    bus_.subscribe<pose_t>(channels::kPose, [this](const pose_t& msg) { on_pose(msg); });
  }

  std::string name() const override { return "map_matcher"; }
  std::vector<std::string> output_channels() const override { return {channels::kMapFix}; }

  StatusReport status() const override {
    StatusReport report;
    report.received = images_ + poses_;
    report.published = published_;
    report.dropped = refusals_[static_cast<int>(FixRefusal::kFrameDropped)];
    report.errors = poses_invalid_ + gate_.rejected();
    if (!origin_) {
      report.state = status_t::STATE_STARTING;
      report.detail = "waiting for the first POSE with INS around it (where the local frame lies)";
    } else if (!last_refusal_.empty()) {
      report.detail = last_refusal_;
    }
    report.counters = {{"attempts", double(attempts_)}, {"fixes", double(published_)},
                       {"poses_invalid", double(poses_invalid_)},
                       {"origin_poses_passed_over", double(pose_origin_.poses_passed_over())}};
    for (int i = 1; i < kFixRefusals; ++i) {
      report.counters.emplace_back(std::string("refused_") + fix_refusal_name(static_cast<FixRefusal>(i)),
                                   double(refusals_[i]));
    }
    gate_.add_counters(&report);
    gate_.warn_if_rejecting(&report);
    return report;
  }

 private:
  void on_image(const image_t& image) {
    ++images_;
    if (have_candidate_time_ && image.utime < next_candidate_utime_) return;
    if (image.pixel_format != image_t::PIXEL_MONO8) {
      refuse(image.utime, FixRefusal::kFrameDropped, "only MONO8 frames are matched");
      return;
    }
    have_candidate_time_ = true;
    next_candidate_utime_ = image.utime + static_cast<int64_t>(options_.interval_s * 1e6);
    // Its POSE may be here already: a lockstep replay delivers the frame to
    // the estimator nodes first, and they can publish its pose before this
    // node sees the frame.
    for (const pose_t& pose : recent_poses_) {
      if (pose.utime == image.utime) {
        match(image, pose);
        return;
      }
    }
    candidates_.push_back(image);
    while (candidates_.size() > 4) drop_oldest("more than 4 frames waiting for their POSE");
  }

  void match(const image_t& image, const pose_t& pose) {
    ++attempts_;
    const FixAttempt attempt = matcher_.attempt(image, pose, *origin_);
    if (attempt.refusal == FixRefusal::kNone) {
      bus_.publish(channels::kMapFix, attempt.fix);
      ++published_;
    } else {
      refuse(pose.utime, attempt.refusal, attempt.why);
    }
  }

  void on_pose(const pose_t& pose) {
    ++poses_;
    if (!pose_finite(pose)) {
      ++poses_invalid_;
      last_refusal_ = "POSE utime " + std::to_string(pose.utime) + ": non-finite values, not used";
      return;
    }
    if (!origin_) {
      pose_origin_.add_pose(pose);
      take_origin();
      if (!origin_) return;
    }
    const int64_t max_age = static_cast<int64_t>(options_.max_frame_age_s * 1e6);
    recent_poses_.push_back(pose);
    while (recent_poses_.size() > 2 && recent_poses_.front().utime < pose.utime - max_age) recent_poses_.pop_front();
    while (!candidates_.empty() && candidates_.front().utime < pose.utime - max_age) {
      drop_oldest("its POSE did not come within max_frame_age_s");
    }
    for (auto it = candidates_.begin(); it != candidates_.end(); ++it) {
      if (it->utime != pose.utime) continue;
      const image_t image = std::move(*it);
      candidates_.erase(it);
      match(image, pose);
      return;
    }
  }

  // Where local north/east (0, 0) lies, and the height of POSE's down 0 (the
  // fixes' ground heights are given on that axis): common/pose_origin.h.
  void take_origin() {
    if (pose_origin_.known()) origin_.emplace(pose_origin_.origin());
  }

  void drop_oldest(const std::string& why) {
    refuse(candidates_.front().utime, FixRefusal::kFrameDropped, why);
    candidates_.pop_front();
  }

  void refuse(int64_t utime, FixRefusal refusal, const std::string& why) {
    ++refusals_[static_cast<int>(refusal)];
    last_refusal_ = std::string("last refused frame ") + std::to_string(utime) + ": " + fix_refusal_name(refusal) +
                    ": " + why;
  }

  MapMatcherOptions options_;
  MapMatcher matcher_;
  InputGate gate_;
  Bus& bus_;
  std::deque<image_t> candidates_;
  PoseOrigin pose_origin_;
  std::deque<pose_t> recent_poses_;  // the last max_frame_age_s of POSE
  std::optional<map::LocalProjection> origin_;
  bool have_candidate_time_ = false;
  int64_t next_candidate_utime_ = 0;
  int64_t images_ = 0, poses_ = 0, poses_invalid_ = 0, attempts_ = 0, published_ = 0;
  std::array<int64_t, kFixRefusals> refusals_{};
  std::string last_refusal_;
};

}  // namespace

std::unique_ptr<Node> make_map_matcher_node(const Config& root, Bus& bus) {
  MapMatcherOptions options = MapMatcherOptions::from_config(root);
  if (options.orthophoto.empty() || options.dem.empty()) {
    throw root.error("map_matcher.orthophoto",
                     "and map_matcher.dem must both name a file: the matcher needs a reference map (docs/maps.md)");
  }
  options.orthophoto = resolve(options.orthophoto);
  options.dem = resolve(options.dem);
  MapMatcher matcher(options, CameraModel::from_config(root), map::ReferenceMap::open(options.orthophoto, options.dem),
                     SensorCalibration::from_config(root).camera_lever_arm_m);
  return std::make_unique<MapMatcherNode>(options, std::move(matcher), InputCheckOptions::from_config(root), bus);
}

void register_map_matcher_node(NodeRegistry& registry) { registry.add("map_matcher", make_map_matcher_node); }

}  // namespace nadir
