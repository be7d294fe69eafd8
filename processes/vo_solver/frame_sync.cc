#include "processes/vo_solver/frame_sync.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

#include "common/geometry.h"

namespace nadir::vo {

void SyncOptions::Check() const {
  auto require = [](bool ok, const std::string& field, const std::string& range) {
    if (!ok) throw std::invalid_argument("sync option " + field + " must be " + range);
  };
  require(ins_min_interval_us >= 0 && ins_min_interval_us <= 1000000, "ins_min_interval_us", "in [0, 1 s]");
  require(max_ins_gap_us > 0 && max_ins_gap_us <= 10000000, "max_ins_gap_us", "in (0, 10 s]");
  require(max_ins_extrapolation_us >= 0 && max_ins_extrapolation_us <= 1000000, "max_ins_extrapolation_us",
          "in [0, 1 s]");
  require(altimeter_staleness_us > 0 && altimeter_staleness_us <= 60000000, "altimeter_staleness_us",
          "in (0, 60 s]");
  require(altimeter_wait_us >= 0 && altimeter_wait_us <= 10000000, "altimeter_wait_us", "in [0, 10 s]");
  require(settle_us >= 0 && settle_us <= 10000000, "settle_us", "in [0, 10 s]");
  require(max_frame_interval_us > 0 && max_frame_interval_us <= 3600000000LL, "max_frame_interval_us", "in (0, 3600 s]");
  require(max_pending_frames >= 1 && max_pending_frames <= 10000, "max_pending_frames", "in [1, 10000]");
  require(max_ins_samples >= 2 && max_ins_samples <= 1000000, "max_ins_samples", "in [2, 1e6]");
  require(max_altimeter_samples >= 2 && max_altimeter_samples <= 1000000, "max_altimeter_samples", "in [2, 1e6]");
  require(max_cached_frames >= 2 && max_cached_frames <= 100000, "max_cached_frames", "in [2, 1e5]");
  calibration.Check();
}

FrameSync::FrameSync(const SyncOptions& options, const Eigen::Vector3d& default_beam_body)
    : options_(options),
      default_beam_body_(default_beam_body.normalized()),
      ins_complete_(options.ins_min_interval_us) {}

void FrameSync::add_ins(const ins_t& ins) {
  if (!std::isfinite(ins.roll) || !std::isfinite(ins.pitch) || !std::isfinite(ins.yaw)) return;
  InsAttitude sample;
  sample.utime = ins.utime;
  sample.roll = ins.roll;
  sample.pitch = ins.pitch;
  sample.yaw = ins.yaw;
  sample.body_rate = Eigen::Vector3d(ins.angular_rate[0], ins.angular_rate[1], ins.angular_rate[2]);
  sample.has_rate = ins.has_rates && sample.body_rate.allFinite();
  if (!sample.has_rate) sample.body_rate.setZero();
  const auto [it, added] = ins_.insert_or_assign(ins.utime, sample);
  if (added) {  // sample times only: what the propagate policy's readiness relies on
    if (it != ins_.begin()) ins_complete_.note_interval(it->first - std::prev(it)->first);
    if (std::next(it) != ins_.end()) ins_complete_.note_interval(std::next(it)->first - it->first);
  }
  while (static_cast<int>(ins_.size()) > options_.max_ins_samples) {
    ins_.erase(ins_.begin());
    ++dropped_samples_;
  }
}

void FrameSync::add_altimeter(const altimeter_t& altimeter) {
  const double range_m = options_.calibration.true_range(altimeter.range_m);
  Range range{altimeter.validity == altimeter_t::VALID_OK && std::isfinite(range_m) && range_m > 0, range_m,
              default_beam_body_};
  const Eigen::Vector3d beam(altimeter.beam_body[0], altimeter.beam_body[1], altimeter.beam_body[2]);
  if (beam.allFinite() && beam.norm() > 0.5) range.beam_body = beam.normalized();
  if (range.valid && options_.calibration.moves_altimeter_ray()) {
    // The solver anchors the ground patch on the point the beam hit, seen from the camera.
    const AltimeterRay ray =
        options_.calibration.ray_from(options_.calibration.camera_lever_arm_m, altimeter.range_m, range.beam_body);
    range.range_m = ray.range_m;
    range.beam_body = ray.beam_body;
  }
  if (!range.valid) ++invalid_altimeter_;
  altimeter_[altimeter.utime] = range;
  while (static_cast<int>(altimeter_.size()) > options_.max_altimeter_samples) {
    altimeter_.erase(altimeter_.begin());
    ++dropped_samples_;
  }
}

bool FrameSync::ins_final(int64_t utime) const {
  if (ins_.empty()) return false;
  const int64_t newest = ins_.rbegin()->first;
  if (newest >= utime + options_.settle_us) return true;
  // Propagate: the newest sample is at or before the frame and the next one
  // cannot be, so the samples at or before it are all here. Not when the
  // channel may reorder itself (settle_us): then only a later sample tells.
  return propagates(options_.attitude_policy, ins_.rbegin()->second.has_rate) && options_.settle_us == 0 &&
         ins_complete_.complete_at(utime, newest);
}

bool FrameSync::ready(int64_t stamp_utime) const {
  if (cache_.count(stamp_utime)) return true;
  const int64_t utime = options_.calibration.exposure_utime(stamp_utime);
  if (!ins_final(utime)) return false;
  if (!options_.altimeter_interpolate) return true;
  const int64_t settled = utime + options_.settle_us;
  if (!altimeter_.empty() && altimeter_.rbegin()->first >= settled) return true;
  return ins_.rbegin()->first >= settled + options_.altimeter_wait_us;
}

const FrameState& FrameSync::frame_state(int64_t utime) {
  auto it = cache_.find(utime);
  if (it != cache_.end()) return it->second;
  it = cache_.emplace(utime, compute(utime)).first;
  while (static_cast<int>(cache_.size()) > options_.max_cached_frames) {
    // Drop the oldest frame, never the one just added.
    if (cache_.begin()->first == utime) break;
    cache_.erase(cache_.begin());
  }
  return it->second;
}

FrameState FrameSync::compute(int64_t stamp_utime) const {
  const int64_t utime = options_.calibration.exposure_utime(stamp_utime);
  FrameState state;
  attitude_at(utime, &state);
  state.range_roll = state.roll;
  state.range_pitch = state.pitch;
  range_at(utime, &state);
  return state;
}

namespace {

void set_attitude(FrameState* state, double roll, double pitch, double yaw) {
  state->has_attitude = true;
  state->roll = roll;
  state->pitch = pitch;
  state->yaw = yaw;
}

}  // namespace

void FrameSync::attitude_at(int64_t utime, FrameState* state) const {
  // `auto` decides by the newest sample at or before the frame: the one
  // ins_final() saw when it let the frame go without a later sample.
  const auto after = ins_.upper_bound(utime);
  const bool base_has_rate = after != ins_.begin() && std::prev(after)->second.has_rate;
  if (propagates(options_.attitude_policy, base_has_rate)) {
    propagate_attitude_to(utime, state);
  } else {
    interpolate_attitude(utime, state);
  }
}

void FrameSync::propagate_attitude_to(int64_t utime, FrameState* state) const {
  auto after = ins_.upper_bound(utime);  // first sample after the frame
  if (after == ins_.begin()) {
    // Nothing at or before the frame (start of the INS): a close later sample as is.
    if (after != ins_.end() && after->first - utime <= options_.max_ins_extrapolation_us) {
      set_attitude(state, after->second.roll, after->second.pitch, after->second.yaw);
    }
    return;
  }
  const auto base = std::prev(after);
  const InsAttitude& a = base->second;
  if (utime - base->first > options_.max_ins_gap_us) return;
  const bool earlier_usable = base != ins_.begin() && base->first - std::prev(base)->first <= options_.max_ins_gap_us;
  const InsAttitude* earlier = earlier_usable ? &std::prev(base)->second : nullptr;
  const auto rpy = propagated_rpy(a, earlier, utime);
  if (rpy) {
    set_attitude(state, rpy->x(), rpy->y(), rpy->z());
    state->attitude_noise_share = propagated_white_noise_share(a, earlier, utime);
  } else if (utime - base->first <= options_.max_ins_extrapolation_us) {
    // One sample and no rate: held, as the interpolate policy holds a one-sided sample.
    set_attitude(state, a.roll, a.pitch, a.yaw);
  }
}

void FrameSync::interpolate_attitude(int64_t utime, FrameState* state) const {
  auto upper = ins_.lower_bound(utime);  // first sample at or after the frame
  const bool has_upper = upper != ins_.end();
  const bool has_lower = upper != ins_.begin();
  auto set = [state](double roll, double pitch, double yaw) { set_attitude(state, roll, pitch, yaw); };
  if (has_upper && upper->first == utime) {
    set(upper->second.roll, upper->second.pitch, upper->second.yaw);
    return;
  }
  if (has_upper && has_lower) {
    auto lower = std::prev(upper);
    if (upper->first - lower->first > options_.max_ins_gap_us) return;
    const double f = static_cast<double>(utime - lower->first) / static_cast<double>(upper->first - lower->first);
    // Slerp between the two attitudes: no wrap problems at +-180 deg yaw.
    const Eigen::Quaterniond qa(rotation_from_rpy(lower->second.roll, lower->second.pitch, lower->second.yaw));
    const Eigen::Quaterniond qb(rotation_from_rpy(upper->second.roll, upper->second.pitch, upper->second.yaw));
    const Eigen::Vector3d rpy = rpy_from_rotation(qa.slerp(f, qb).toRotationMatrix());
    set(rpy.x(), rpy.y(), rpy.z());
    state->attitude_noise_share = interpolated_white_noise_share(f);
    return;
  }
  if (has_upper && upper->first - utime <= options_.max_ins_extrapolation_us) {
    set(upper->second.roll, upper->second.pitch, upper->second.yaw);
  } else if (has_lower && utime - std::prev(upper)->first <= options_.max_ins_extrapolation_us) {
    const auto& a = std::prev(upper)->second;
    set(a.roll, a.pitch, a.yaw);
  }
}

void FrameSync::range_at(int64_t utime, FrameState* state) const {
  // Nearest valid samples on each side of the frame.
  // Without interpolation only samples before the frame count, so the result
  // cannot depend on whether a later sample had arrived (live = replay) --
  // nor on whether one stamped exactly at the frame time came before or after
  // the INS sample that made the frame ready (the simulator's 10 Hz altimeter
  // and 14 Hz camera share a time every 0.5 s).
  const bool interpolate = options_.altimeter_interpolate;
  auto after = interpolate ? altimeter_.lower_bound(utime) : altimeter_.end();
  while (after != altimeter_.end() && !after->second.valid) ++after;
  auto before = altimeter_.lower_bound(utime);
  bool has_before = false;
  while (before != altimeter_.begin()) {
    --before;
    if (before->second.valid) {
      has_before = true;
      break;
    }
  }
  const bool has_after = after != altimeter_.end();
  if (!has_before && !has_after) return;
  const int64_t dt_before = has_before ? utime - before->first : INT64_MAX;
  const int64_t dt_after = has_after ? after->first - utime : INT64_MAX;
  const int64_t limit = options_.altimeter_staleness_us;
  state->has_range = true;
  if (dt_before <= limit && dt_after <= limit && dt_after > 0) {
    const double span = static_cast<double>(after->first - before->first);
    const double f = span > 0 ? static_cast<double>(dt_before) / span : 0.0;
    state->range_m = before->second.range_m + f * (after->second.range_m - before->second.range_m);
    state->beam_body = (f < 0.5 ? before : after)->second.beam_body;
    return;
  }
  const auto& nearest = dt_before <= dt_after ? before->second : after->second;
  state->range_m = nearest.range_m;
  state->range_age_us = dt_before <= dt_after ? dt_before : -dt_after;
  FrameState then;
  attitude_at(utime - state->range_age_us, &then);
  if (then.has_attitude) {
    state->range_roll = then.roll;
    state->range_pitch = then.pitch;
  }
  state->beam_body = nearest.beam_body;
  state->range_stale = std::min(dt_before, dt_after) > limit;
}

}  // namespace nadir::vo
