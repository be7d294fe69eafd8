#pragma once
// Horizontal protection level of a POSE: a radius the true horizontal error
// stays within with probability `probability` (per pose, Gaussian errors with
// the reported covariance). With sigma_max^2 the largest eigenvalue of the
// 2x2 horizontal covariance, P(|e| <= k sigma_max) >= P(chi2_2 <= k^2) =
// 1 - exp(-k^2 / 2), so k = sqrt(-2 ln(1 - probability)): 3.035 at 99 %. A
// pose flagged as dead-reckoned or degraded (VO gap, no altimeter, coasting)
// gets it times flagged_inflation; an initialising one has none (-1).

#include <Eigen/Core>

#include <cstdint>

#include "nadir/pose_t.hpp"

namespace nadir {

struct ProtectionLevelOptions {
  double probability = 0.99;      // yaw_fusion.protection_level.probability
  double flagged_inflation = 2.0; // yaw_fusion.protection_level.flagged_inflation
  // The factor k on the largest horizontal sigma.
  double sigma_factor() const;
};

// The pose_t flags that inflate the protection level, and the one that leaves none.
constexpr int32_t kProtectionLevelInflatingFlags =
    pose_t::FLAG_VO_GAP | pose_t::FLAG_NO_ALTIMETER | pose_t::FLAG_COASTING;
constexpr int32_t kProtectionLevelUnavailableFlags = pose_t::FLAG_INITIALIZING;

// Metres; -1 when unavailable (initialising, or a covariance that is not finite).
double horizontal_protection_level(const Eigen::Matrix2d& horizontal_covariance, int32_t flags,
                                   const ProtectionLevelOptions& options);

}  // namespace nadir
