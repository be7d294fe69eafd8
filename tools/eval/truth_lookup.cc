#include "tools/eval/truth_lookup.h"

#include <algorithm>

#include "common/geometry.h"

namespace nadir {

bool truth_at(const std::vector<ground_truth_t>& truth, int64_t utime, TruthAt* out) {
  if (truth.empty() || utime < truth.front().utime - kTruthExtrapolationMaxUs ||
      utime > truth.back().utime + kTruthExtrapolationMaxUs) {
    return false;
  }
  if (utime < truth.front().utime || utime > truth.back().utime) {
    const ground_truth_t& end = utime < truth.front().utime ? truth.front() : truth.back();
    const double dt = static_cast<double>(utime - end.utime) * 1e-6;
    for (int i = 0; i < 3; ++i) {
      out->position[i] = end.position_ned[i] + dt * end.velocity_ned[i];
      out->velocity[i] = end.velocity_ned[i];
    }
    out->roll = end.roll;
    out->pitch = end.pitch;
    out->yaw = end.yaw;
    out->height_agl_m = end.height_agl_m;
    return true;
  }
  auto it = std::lower_bound(truth.begin(), truth.end(), utime,
                             [](const ground_truth_t& t, int64_t u) { return t.utime < u; });
  const ground_truth_t& b = *it;
  const ground_truth_t& a = it == truth.begin() ? b : *(it - 1);
  const double span = static_cast<double>(b.utime - a.utime);
  const double w = span > 0 ? static_cast<double>(utime - a.utime) / span : 1.0;
  for (int i = 0; i < 3; ++i) {
    out->position[i] = a.position_ned[i] + w * (b.position_ned[i] - a.position_ned[i]);
    out->velocity[i] = a.velocity_ned[i] + w * (b.velocity_ned[i] - a.velocity_ned[i]);
  }
  out->roll = wrap_angle(a.roll + w * angle_difference(b.roll, a.roll));
  out->pitch = a.pitch + w * (b.pitch - a.pitch);
  out->yaw = wrap_angle(a.yaw + w * angle_difference(b.yaw, a.yaw));
  out->height_agl_m = a.height_agl_m + w * (b.height_agl_m - a.height_agl_m);
  return true;
}

}  // namespace nadir
