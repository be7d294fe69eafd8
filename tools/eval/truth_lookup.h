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
// the wrap; false outside the truth span.
bool truth_at(const std::vector<ground_truth_t>& truth, int64_t utime, TruthAt* out);

}  // namespace nadir
