#include "tools/eval/coast_metrics.h"

#include <cmath>

#include "tools/eval/trajectory_metrics.h"

namespace nadir {
namespace {

double error_n(const EvalSample& s) { return s.estimate[0] - s.truth[0]; }
double error_e(const EvalSample& s) { return s.estimate[1] - s.truth[1]; }

CoastEpisode episode(const EvalSample& before, const EvalSample& end) {
  CoastEpisode c;
  c.start_s = before.t_s;
  c.duration_s = end.t_s - before.t_s;
  c.added_h_m = std::hypot(error_n(end) - error_n(before), error_e(end) - error_e(before));
  c.added_v_m = end.error_v_m - before.error_v_m;
  c.error_h_m = end.error_h_m;
  c.sigma_h_m = end.sigma_h_m;
  return c;
}

}  // namespace

std::vector<CoastEpisode> coast_episodes(const std::vector<EvalSample>& samples, int32_t coasting_flag) {
  std::vector<CoastEpisode> out;
  size_t i = 0;
  while (i < samples.size()) {
    if (!(samples[i].flags & coasting_flag)) {
      ++i;
      continue;
    }
    const size_t before = i > 0 ? i - 1 : 0;
    size_t end = i;
    while (end + 1 < samples.size() && (samples[end + 1].flags & coasting_flag)) ++end;
    out.push_back(episode(samples[before], samples[end]));
    i = end + 1;
  }
  return out;
}

}  // namespace nadir
