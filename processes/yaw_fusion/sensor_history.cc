#include "processes/yaw_fusion/sensor_history.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "common/geometry.h"

namespace nadir {

namespace {

// Index of the first sample with utime > t.
template <class Sample>
size_t upper_index(const std::deque<Sample>& samples, int64_t t) {
  const auto it = std::upper_bound(samples.begin(), samples.end(), t,
                                   [](int64_t value, const Sample& s) { return value < s.utime; });
  return static_cast<size_t>(it - samples.begin());
}

// Keeps the last `keep` samples at or before t (a query at t needs them) and all after.
template <class Sample>
void forget_samples_before(std::deque<Sample>* samples, int64_t t, size_t keep = 1) {
  while (samples->size() > keep && (*samples)[keep].utime <= t) samples->pop_front();
}

}  // namespace

bool InsHistory::add(const AttitudeSample& sample) {
  if (!insert_sorted(&samples_, sample)) return false;
  // Sample times only: what the propagate policy's completeness relies on.
  const size_t i = upper_index(samples_, sample.utime) - 1;
  if (i > 0) complete_.note_interval(samples_[i].utime - samples_[i - 1].utime);
  if (i + 1 < samples_.size()) complete_.note_interval(samples_[i + 1].utime - samples_[i].utime);
  while (samples_.size() > capacity_) {
    samples_.pop_front();
    ++dropped_;
  }
  return true;
}

namespace {

InsAttitude ins_attitude(const AttitudeSample& s) {
  InsAttitude a;
  a.utime = s.utime;
  a.roll = s.roll;
  a.pitch = s.pitch;
  a.yaw = s.yaw;
  a.has_rate = s.has_rate;
  a.body_rate = s.body_rate;
  return a;
}

}  // namespace

std::optional<AttitudeSample> InsHistory::at(int64_t utime, int64_t max_bracket_us, AttitudePolicy policy) const {
  if (samples_.empty()) return std::nullopt;
  const size_t upper = upper_index(samples_, utime);
  const AttitudeSample* before = upper > 0 ? &samples_[upper - 1] : nullptr;
  const AttitudeSample* after = upper < samples_.size() ? &samples_[upper] : nullptr;
  if (before != nullptr && before->utime == utime) return *before;
  if (before != nullptr && propagates(policy, before->has_rate)) {
    // Never the later sample: the answer must not depend on whether it has arrived.
    if (utime - before->utime > max_bracket_us) return std::nullopt;
    const AttitudeSample* earlier = upper > 1 ? &samples_[upper - 2] : nullptr;
    const InsAttitude earlier_attitude = earlier != nullptr ? ins_attitude(*earlier) : InsAttitude{};
    const bool earlier_usable = earlier != nullptr && before->utime - earlier->utime <= max_bracket_us;
    AttitudeSample out = *before;
    out.utime = utime;
    const InsAttitude base = ins_attitude(*before);
    const InsAttitude* earlier_used = earlier_usable ? &earlier_attitude : nullptr;
    if (const auto rpy = propagated_rpy(base, earlier_used, utime)) {
      out.roll = rpy->x();
      out.pitch = rpy->y();
      out.yaw = rpy->z();
      out.white_noise_share = propagated_white_noise_share(base, earlier_used, utime);
      if (out.yaw_variance >= 0.0) out.yaw_variance *= out.white_noise_share;
    }
    return out;
  }
  if (before != nullptr && after != nullptr && after->utime - before->utime <= max_bracket_us) {
    const double f = static_cast<double>(utime - before->utime) / static_cast<double>(after->utime - before->utime);
    AttitudeSample out;
    out.utime = utime;
    out.roll = before->roll + f * angle_difference(after->roll, before->roll);
    out.pitch = before->pitch + f * angle_difference(after->pitch, before->pitch);
    out.yaw = wrap_angle(before->yaw + f * angle_difference(after->yaw, before->yaw));
    out.white_noise_share = interpolated_white_noise_share(f);
    out.yaw_variance = (before->yaw_variance < 0.0 || after->yaw_variance < 0.0)
                           ? -1.0
                           : (1.0 - f) * (1.0 - f) * before->yaw_variance + f * f * after->yaw_variance;
    return out;
  }
  const AttitudeSample* nearest = nullptr;
  if (before != nullptr && utime - before->utime <= max_bracket_us) nearest = before;
  if (after != nullptr && after->utime - utime <= max_bracket_us &&
      (nearest == nullptr || after->utime - utime < utime - nearest->utime)) {
    nearest = after;
  }
  if (nearest == nullptr) return std::nullopt;
  AttitudeSample out = *nearest;
  out.utime = utime;
  return out;
}

// Two: propagating without INS rates takes the rate from the two newest samples.
void InsHistory::forget_before(int64_t utime) { forget_samples_before(&samples_, utime, 2); }

bool AltimeterHistory::add(const RangeSample& sample) {
  note_time(sample.utime);
  if (!insert_sorted(&samples_, sample)) return false;
  while (samples_.size() > capacity_) {
    samples_.pop_front();
    ++dropped_;
  }
  return true;
}

double vertical_range(double range_m, const Eigen::Vector3d& beam_body, double roll, double pitch) {
  return level_range(range_m, beam_body, roll, pitch).z();
}

Eigen::Vector3d level_range(double range_m, const Eigen::Vector3d& beam_body, double roll, double pitch) {
  return range_m * (rotation_from_rpy(roll, pitch, 0.0) * beam_body.normalized());
}

std::optional<double> AltimeterHistory::height_agl(int64_t utime, int64_t max_age_us, double roll, double pitch,
                                                   bool use_later) const {
  const auto beam = beam_level(utime, max_age_us, roll, pitch, use_later);
  if (!beam) return std::nullopt;
  return beam->z();
}

std::optional<Eigen::Vector3d> AltimeterHistory::beam_level(int64_t utime, int64_t max_age_us, double roll,
                                                            double pitch, bool use_later) const {
  if (samples_.empty()) return std::nullopt;
  // Without later samples only those before the frame count: one stamped
  // exactly at the frame time may arrive after the delta (live) or before it
  // (replay), and the result must not depend on that.
  const size_t upper = upper_index(samples_, use_later ? utime : utime - 1);
  const RangeSample* before = upper > 0 ? &samples_[upper - 1] : nullptr;
  const RangeSample* after = use_later && upper < samples_.size() ? &samples_[upper] : nullptr;
  if (before != nullptr && utime - before->utime > max_age_us) before = nullptr;
  if (after != nullptr && after->utime - utime > max_age_us) after = nullptr;
  if (before != nullptr && after != nullptr && after->utime > before->utime) {
    const double f = static_cast<double>(utime - before->utime) / static_cast<double>(after->utime - before->utime);
    const double range = before->range_m + f * (after->range_m - before->range_m);
    return level_range(range, before->beam_body, roll, pitch);
  }
  const RangeSample* nearest = before != nullptr ? before : after;
  if (before != nullptr && after != nullptr && after->utime - utime < utime - before->utime) nearest = after;
  if (nearest == nullptr) return std::nullopt;
  return level_range(nearest->range_m, nearest->beam_body, roll, pitch);
}

std::vector<RangeSample> AltimeterHistory::between(int64_t from, int64_t to) const {
  std::vector<RangeSample> out;
  for (size_t i = upper_index(samples_, from - 1); i < samples_.size() && samples_[i].utime < to; ++i) {
    out.push_back(samples_[i]);
  }
  return out;
}

void AltimeterHistory::forget_before(int64_t utime) { forget_samples_before(&samples_, utime); }

}  // namespace nadir
