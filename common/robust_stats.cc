#include "common/robust_stats.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace nadir {
namespace {

void check_input(const std::vector<double>& values, const char* function) {
  if (values.empty()) throw std::invalid_argument(std::string(function) + ": empty input (a median needs a value)");
  for (size_t i = 0; i < values.size(); ++i)
    if (std::isnan(values[i]))
      throw std::invalid_argument(std::string(function) + ": NaN at index " + std::to_string(i) + " of " +
                                  std::to_string(values.size()));
}

// Selection, not a full sort: O(n). For an even count the lower middle value
// is the largest of the lower half once nth_element has partitioned it.
double select_median(std::vector<double>& v, EvenMedian even) {
  const size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
  const double upper = v[m];
  if (v.size() % 2 == 1 || even == EvenMedian::kUpper) return upper;
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m)));
}

}  // namespace

double median(std::vector<double> values, EvenMedian even) {
  check_input(values, "median");
  return select_median(values, even);
}

double median_abs(std::vector<double> values, EvenMedian even) {
  check_input(values, "median_abs");
  for (double& x : values) x = std::fabs(x);
  return select_median(values, even);
}

double mad_sigma(const std::vector<double>& values, EvenMedian even) {
  check_input(values, "mad_sigma");
  const double centre = median(values, even);
  std::vector<double> deviations;
  deviations.reserve(values.size());
  for (double x : values) deviations.push_back(std::fabs(x - centre));
  return kMadToSigma * select_median(deviations, even);
}

double abs_sigma(std::vector<double> residuals, EvenMedian even) {
  check_input(residuals, "abs_sigma");
  return kMadToSigma * median_abs(std::move(residuals), even);
}

}  // namespace nadir
