#include "tools/eval/consistency.h"

#include <cmath>

namespace nadir {

double horizontal_nees(double error_n, double error_e, double p_nn, double p_ne, double p_ee) {
  const double det = p_nn * p_ee - p_ne * p_ne;
  if (!(p_nn > 0.0) || !(det > 1e-12 * p_nn * p_ee) || !(det > 0.0)) return -1.0;
  // [e_n e_e] [p_ee -p_ne; -p_ne p_nn] / det [e_n e_e]'
  return (error_n * error_n * p_ee - 2.0 * error_n * error_e * p_ne + error_e * error_e * p_nn) / det;
}

double scalar_nees(double error, double variance) { return variance > 0.0 ? error * error / variance : -1.0; }

void NeesSummary::add(double nees) {
  if (!(nees >= 0.0)) return;
  ++n_;
  sum_ += nees;
  if (nees <= chi2_95_) ++within_;
}

void ProtectionLevelSummary::add(double error_h_m, double protection_level_m) {
  if (!(protection_level_m >= 0.0) || !std::isfinite(error_h_m)) {
    ++unavailable_;
    return;
  }
  ++n_;
  if (error_h_m > protection_level_m) ++exceeded_;
}

}  // namespace nadir
