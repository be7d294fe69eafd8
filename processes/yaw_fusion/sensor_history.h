#pragma once
// Time-ordered buffers of INS attitude and altimeter range, queried at frame
// (sensor) time. Samples are kept sorted by utime whatever their arrival
// order, so a query gives the same answer in a live run and in a replay once
// the samples around the query time are there.

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <vector>

#include "common/attitude_propagation.h"

namespace nadir {

struct AttitudeSample {
  int64_t utime = 0;
  double roll = 0.0;
  double pitch = 0.0;
  double yaw = 0.0;
  double yaw_variance = -1.0;  // < 0: this sample's yaw must not be used
  // The share of one INS sample's white noise variance in this attitude
  // (attitude_propagation.h): 1 for a sample as the INS gave it; the frame
  // attitude InsHistory::at makes from two samples has less, and its
  // yaw_variance is scaled by it.
  double white_noise_share = 1.0;
  bool has_rate = false;       // body_rate is the INS's own
  Eigen::Vector3d body_rate = Eigen::Vector3d::Zero();  // rad/s
};

// Inserts `value` into a deque sorted by utime; false for a duplicate utime.
// Drops the oldest when over capacity (counted by the caller via the return).
template <class Sample>
bool insert_sorted(std::deque<Sample>* samples, const Sample& value) {
  auto it = samples->end();
  while (it != samples->begin() && std::prev(it)->utime > value.utime) --it;
  if (it != samples->begin() && std::prev(it)->utime == value.utime) return false;
  samples->insert(it, value);
  return true;
}

class InsHistory {
 public:
  // min_interval_us: INS samples are never closer (propagate policy, see
  // common/attitude_propagation.h).
  explicit InsHistory(size_t capacity = 4096, int64_t min_interval_us = 9000)
      : capacity_(capacity), complete_(min_interval_us) {}

  // False for a duplicate utime (ignored).
  bool add(const AttitudeSample& sample);
  // Latest sample time, or INT64_MIN when empty.
  int64_t newest_utime() const {
    return samples_.empty() ? std::numeric_limits<int64_t>::min() : samples_.back().utime;
  }
  // Attitude at t. interpolate: between the samples around t when they are at
  // most max_bracket_us apart; otherwise the nearest sample within
  // max_bracket_us of t; otherwise nothing. The yaw is usable only when both
  // interpolated samples' yaws are (variance = the larger one). propagate: the
  // newest sample at or before t (within max_bracket_us), rotated on to t with
  // its rate or the rate from the sample before it, held when there is none;
  // a later sample only when none is at or before t.
  std::optional<AttitudeSample> at(int64_t utime, int64_t max_bracket_us,
                                   AttitudePolicy policy = AttitudePolicy::kInterpolate) const;
  // propagate: every sample at or before `utime` is in (no sample after it needed).
  bool complete_at(int64_t utime) const { return complete_.complete_at(utime, newest_utime()); }
  bool newest_has_rate() const { return !samples_.empty() && samples_.back().has_rate; }
  int64_t short_intervals() const { return complete_.short_intervals(); }
  // Forgets samples no query at or after `utime` can need.
  void forget_before(int64_t utime);
  size_t size() const { return samples_.size(); }
  int64_t dropped() const { return dropped_; }

 private:
  size_t capacity_;
  std::deque<AttitudeSample> samples_;
  int64_t dropped_ = 0;
  InsCompleteness complete_;
};

struct RangeSample {
  int64_t utime = 0;
  double range_m = 0.0;
  Eigen::Vector3d beam_body = Eigen::Vector3d::UnitZ();
};

class AltimeterHistory {
 public:
  explicit AltimeterHistory(size_t capacity = 4096) : capacity_(capacity) {}

  // Valid ranges only. False for a duplicate utime.
  bool add(const RangeSample& sample);
  // Any altimeter message (valid or not) tells how far the altimeter's time has got.
  void note_time(int64_t utime) { newest_ = std::max(newest_, utime); }
  int64_t newest_utime() const { return newest_; }
  // Height above (level) ground at t: the slant range interpolated between
  // the valid samples around t (both within max_age_us of t), else the
  // nearest within max_age_us, else nothing; levelled with the roll and pitch
  // at t. (Not with the INS at each sample's own time: the INS after t may
  // not have arrived yet, and the answer must not depend on arrival order.)
  // With `use_later` false only samples at or before t count (no waiting for
  // the next sample; the answer cannot depend on whether it has arrived).
  std::optional<double> height_agl(int64_t utime, int64_t max_age_us, double roll, double pitch,
                                   bool use_later = true) const;
  // The same range as a vector in the level vehicle frame (x forward, y
  // right, z down: z is height_agl), to the ground spot the beam hits.
  std::optional<Eigen::Vector3d> beam_level(int64_t utime, int64_t max_age_us, double roll, double pitch,
                                            bool use_later = true) const;
  // The valid samples from `from` (inclusive) to `to` (exclusive), oldest first.
  std::vector<RangeSample> between(int64_t from, int64_t to) const;
  void forget_before(int64_t utime);
  int64_t dropped() const { return dropped_; }

 private:
  size_t capacity_;
  std::deque<RangeSample> samples_;
  int64_t newest_ = std::numeric_limits<int64_t>::min();
  int64_t dropped_ = 0;
};

// Vertical component of a body-frame beam of length range_m after levelling
// by roll and pitch (ZYX; yaw does not matter).
double vertical_range(double range_m, const Eigen::Vector3d& beam_body, double roll, double pitch);
// The range as a vector in the level frame (its z is vertical_range).
Eigen::Vector3d level_range(double range_m, const Eigen::Vector3d& beam_body, double roll, double pitch);

}  // namespace nadir
