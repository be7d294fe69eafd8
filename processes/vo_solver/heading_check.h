#pragma once
// The solved heading change against the INS's: a pair whose fitted dyaw
// differs from the INS heading change between its two frames by more than a
// bound is not a good solve (a photo saved rotated, features matched to the
// wrong place), however small its residual. Only the rotation is checked: the
// INS gives no motion direction that is not GPS.

namespace nadir::vo {

struct HeadingCheckOptions {
  // Largest |solved dyaw - INS heading change| of a good pair, rad; 0 = off.
  // The INS heading change between two frames is accurate to a degree or two
  // (its noise and a gimbal's yaw error do not add up over one pair), and
  // the solved dyaw to a fraction of that: 20 deg is far outside both, and a
  // photo rotated by 90 or 180 deg is far beyond it.
  double max_dyaw_vs_ins_rad = 0.3490658503988659;  // 20 deg
};

// True when the bound is on and |wrap(solved_dyaw - (curr_yaw - prev_yaw))| exceeds it.
bool heading_contradicts_ins(double solved_dyaw, double prev_yaw, double curr_yaw,
                             const HeadingCheckOptions& options);

}  // namespace nadir::vo
