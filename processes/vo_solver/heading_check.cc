#include "processes/vo_solver/heading_check.h"

#include <cmath>

#include "common/geometry.h"

namespace nadir::vo {

bool heading_contradicts_ins(double solved_dyaw, double prev_yaw, double curr_yaw,
                             const HeadingCheckOptions& options) {
  if (!(options.max_dyaw_vs_ins_rad > 0)) return false;
  const double ins_dyaw = angle_difference(curr_yaw, prev_yaw);
  return !(std::abs(wrap_angle(solved_dyaw - ins_dyaw)) <= options.max_dyaw_vs_ins_rad);
}

}  // namespace nadir::vo
