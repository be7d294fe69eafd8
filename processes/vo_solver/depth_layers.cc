#include "processes/vo_solver/depth_layers.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nadir::vo {

void DepthLayerOptions::Check() const {
  if (!(min_fraction > 0 && min_fraction <= 0.5)) throw std::invalid_argument("layer_min_fraction must be in (0, 0.5]");
  if (!(min_separation >= 0 && min_separation <= 10)) {
    throw std::invalid_argument("layer_min_separation must be in [0, 10]");
  }
  if (!(min_separation_sigma >= 3 && min_separation_sigma <= 100)) {
    throw std::invalid_argument("layer_min_separation_sigma must be in [3, 100]");
  }
}

bool split_into_depth_layers(std::vector<double> offsets, const DepthLayerOptions& options) {
  offsets.erase(std::remove_if(offsets.begin(), offsets.end(), [](double x) { return !std::isfinite(x); }),
                offsets.end());
  const size_t n = offsets.size();
  const size_t min_size = std::max<size_t>(5, static_cast<size_t>(std::ceil(options.min_fraction * n)));
  if (n < 2 * min_size) return false;
  std::sort(offsets.begin(), offsets.end());
  // Prefix sums: the within-group sum of squares of every split in O(n).
  std::vector<double> sum(n + 1, 0.0), sum_sq(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) {
    sum[i + 1] = sum[i] + offsets[i];
    sum_sq[i + 1] = sum_sq[i] + offsets[i] * offsets[i];
  }
  auto within = [&](size_t a, size_t b) {
    return sum_sq[b] - sum_sq[a] - (sum[b] - sum[a]) * (sum[b] - sum[a]) / (b - a);
  };
  size_t best = 0;
  double best_ss = INFINITY;
  for (size_t k = min_size; k + min_size <= n; ++k) {
    const double ss = within(0, k) + within(k, n);
    if (ss < best_ss) {
      best_ss = ss;
      best = k;
    }
  }
  const double gap = (sum[n] - sum[best]) / (n - best) - sum[best] / best;
  const double pooled_sigma = std::sqrt(std::max(0.0, best_ss) / (n - 2));
  return gap > options.min_separation && gap > options.min_separation_sigma * pooled_sigma;
}

}  // namespace nadir::vo
