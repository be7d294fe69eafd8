#include "common/pose_origin.h"

#include <stdexcept>

namespace nadir {

namespace {

constexpr size_t kMaxInsSamples = 400;  // 4 s at 100 Hz
constexpr size_t kMaxPendingPoses = 256;

GeodeticPoint ins_point(const ins_t& s) { return {s.latitude_deg, s.longitude_deg, s.height_m}; }

// The INS position `dt_us` after sample `s`, along its velocity.
GeodeticPoint moved_along_velocity(const ins_t& s, int64_t dt_us) {
  const double dt = static_cast<double>(dt_us) * 1e-6;
  GeodeticTrack track(ins_point(s));
  return track.geodetic(Eigen::Vector3d(s.velocity_ned[0], s.velocity_ned[1], s.velocity_ned[2]) * dt);
}

}  // namespace

PoseOrigin::PoseOrigin(double max_extrapolation_s) {
  if (!(max_extrapolation_s >= 0.0 && max_extrapolation_s <= 1.0)) {
    throw std::invalid_argument("PoseOrigin: max_extrapolation_s must be in [0, 1] s");
  }
  max_extrapolation_us_ = static_cast<int64_t>(max_extrapolation_s * 1e6);
}

void PoseOrigin::add_ins(const ins_t& ins) {
  if (known()) return;
  if (!ins_.empty() && ins.utime <= ins_.back().utime) return;  // out of order: the gate counts those
  ins_.push_back(ins);
  while (ins_.size() > kMaxInsSamples) ins_.pop_front();
  resolve();
}

void PoseOrigin::add_pose(const pose_t& pose) {
  if (known()) return;
  if (poses_.size() < kMaxPendingPoses) {
    poses_.push_back({pose.utime, Eigen::Vector3d(pose.position_ned[0], pose.position_ned[1], pose.position_ned[2])});
  }
  resolve();
}

void PoseOrigin::resolve() {
  while (!known() && !poses_.empty() && !ins_.empty()) {
    const PendingPose& pose = poses_.front();
    const ins_t* before = nullptr;
    const ins_t* after = nullptr;
    for (const ins_t& s : ins_) {
      if (s.utime <= pose.utime) before = &s;
      if (s.utime >= pose.utime) {
        after = &s;
        break;
      }
    }
    if (after == nullptr) {
      // The INS has not reached the pose's time yet: wait for it.
      return;
    }
    if (before != nullptr) {
      if (before == after) {
        anchor(pose, ins_point(*after));
        return;
      }
      const double f = static_cast<double>(pose.utime - before->utime) / static_cast<double>(after->utime - before->utime);
      GeodeticPoint at;
      at.latitude_deg = before->latitude_deg + f * (after->latitude_deg - before->latitude_deg);
      at.longitude_deg = before->longitude_deg + f * (after->longitude_deg - before->longitude_deg);
      at.height_m = before->height_m + f * (after->height_m - before->height_m);
      anchor(pose, at);
      return;
    }
    // The INS starts after this pose.
    if (after->utime - pose.utime <= max_extrapolation_us_) {
      anchor(pose, moved_along_velocity(*after, pose.utime - after->utime));
      return;
    }
    ++passed_over_;
    poses_.pop_front();
  }
}

void PoseOrigin::anchor(const PendingPose& pose, const GeodeticPoint& ins_at_pose) {
  GeodeticTrack track(ins_at_pose);
  origin_ = track.geodetic(-pose.position_ned);  // down: the origin's height is the INS's plus the pose's down
  anchored_utime_ = pose.utime;
  ins_.clear();
  poses_.clear();
}

}  // namespace nadir
