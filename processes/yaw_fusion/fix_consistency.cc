#include "processes/yaw_fusion/fix_consistency.h"

#include <cmath>

namespace nadir {

namespace {

// The standard normal's p-quantile (Acklam's rational approximation, relative
// error under 1.2e-9), for p in (0.5, 1).
double normal_quantile_upper(double p) {
  const double q = std::sqrt(-2.0 * std::log(1.0 - p));
  const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                      -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00, 3.754408661907416e+00};
  if (1.0 - p < 0.02425) {
    return -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                      1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                      6.680131188771972e+01,  -1.328068155288572e+01};
  const double r0 = p - 0.5, r = r0 * r0;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * r0 /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

}  // namespace

double chi_square_quantile(double p, int dof) {
  const double k = static_cast<double>(dof);
  const double z = normal_quantile_upper(p);
  const double v = 2.0 / (9.0 * k);
  const double cube = 1.0 - v + z * std::sqrt(v);
  return k * cube * cube * cube;
}

double FixConsistency::inflation() const {
  if (window_ <= 0 || static_cast<int>(nis_.size()) < window_) return 1.0;
  double sum = 0.0;
  for (const double n : nis_) sum += n;
  const int dof = dof_ * window_;
  if (!(sum > chi_square_quantile(0.99, dof))) return 1.0;
  return sum / dof;
}

void FixConsistency::note(double nis) {
  if (window_ <= 0 || !std::isfinite(nis)) return;
  nis_.push_back(nis);
  while (static_cast<int>(nis_.size()) > window_) nis_.pop_front();
}

}  // namespace nadir
