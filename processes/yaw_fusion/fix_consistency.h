#pragma once
// Whether the pose's covariance holds what the map fixes see. When it does,
// a fix's normalised innovation squared (NIS, innovation' S^-1 innovation)
// is chi-square with one degree of freedom per axis measured, and the sum
// over the last `window` fixes of one kind with window * dof. Beyond that
// sum's 99 % quantile the fixes keep disagreeing with the pose by more than
// its covariance and theirs allow: a drift the pose's model does not hold
// (an installation calibrated on too short a flight, a climb error), which
// the map's systematic error, carried as a consider parameter, would
// otherwise absorb -- the pose would take each fix as the map's offset and
// not move. The next fix then inflates the pose's covariance by the mean NIS
// per degree of freedom (covariance matching), so that the fix moves it and
// the reported covariance says what was seen. What the window holds is the
// NIS after that inflation: once the pose agrees, the inflation stops.

#include <deque>

namespace nadir {

// The p-quantile of the chi-square distribution with `dof` degrees of
// freedom (Wilson-Hilferty; within 0.5 % of the exact value from 10 degrees
// of freedom on at p = 0.99). p in (0.5, 1).
double chi_square_quantile(double p, int dof);

class FixConsistency {
 public:
  // `dof`: axes per fix (2 horizontal, 1 vertical); `window` fixes (0: never inflate).
  FixConsistency(int dof, int window) : dof_(dof), window_(window) {}

  // The factor (>= 1) the pose's covariance of these axes takes before the next fix.
  double inflation() const;
  // The NIS of a fix that was applied (not one gated out).
  void note(double nis);

 private:
  int dof_;
  int window_;
  std::deque<double> nis_;
};

}  // namespace nadir
