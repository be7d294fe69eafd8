#pragma once
// Robust statistics shared by the calibration, import and evaluation tools:
// the median, the median of absolute values and the MAD-based sigma.
//
// Every function takes its input by value (it reorders a copy) and throws
// std::invalid_argument for an empty input or one holding a NaN: a median of
// nothing has no value, and NaN breaks the ordering the selection relies on.

#include <vector>

namespace nadir {

// Which value stands for the median of an even number of values.
enum class EvenMedian {
  kMidpoint,  // the mean of the two middle values (the textbook median)
  kUpper,     // the upper middle value, v[n / 2] once sorted: always one of the inputs
};

// Sigma of a normal distribution from its median absolute deviation.
inline constexpr double kMadToSigma = 1.4826;

double median(std::vector<double> values, EvenMedian even = EvenMedian::kMidpoint);

// Median of |x|: the typical size of residuals about zero.
double median_abs(std::vector<double> values, EvenMedian even = EvenMedian::kMidpoint);

// Robust sigma about the median: kMadToSigma * median(|x - median(x)|).
double mad_sigma(const std::vector<double>& values, EvenMedian even = EvenMedian::kMidpoint);

// Robust sigma of residuals about zero: kMadToSigma * median(|x|).
double abs_sigma(std::vector<double> residuals, EvenMedian even = EvenMedian::kMidpoint);

}  // namespace nadir
