#pragma once
// Truth at any sensor time: GROUND_TRUTH interpolated between its samples.

#include <array>
#include <cstdint>
#include <vector>

#include "nadir/ground_truth_t.hpp"

namespace nadir {

struct TruthAt {
  std::array<double, 3> position;
  std::array<double, 3> velocity;
  double roll, pitch, yaw;
  double height_agl_m;  // body height above the terrain below
};

// Linear interpolation of `truth` (sorted by utime) at `utime`, angles across
// the wrap. Within kTruthExtrapolationMaxUs before the first sample or after
// the last, the end sample moved along its velocity (a flight's first frame
// can be exposed a few microseconds before the truth starts, and it is POSE's
// origin); false further outside.
constexpr int64_t kTruthExtrapolationMaxUs = 20'000;
bool truth_at(const std::vector<ground_truth_t>& truth, int64_t utime, TruthAt* out);
bool truth_at(const std::vector<ground_truth_t>& truth, int64_t utime, TruthAt* out);

}  // namespace nadir
