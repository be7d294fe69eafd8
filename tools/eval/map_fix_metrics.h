#pragma once
// How the map matcher's fixes (MAP_FIX) compare with the truth at their
// frames, and what yaw fusion did with them (POSE flags).

#include <cstdint>
#include <string>
#include <vector>

#include "nadir/ground_truth_t.hpp"
#include "nadir/map_fix_t.hpp"
#include "nadir/pose_t.hpp"
#include "tools/eval/truth_lookup.h"

namespace nadir {

// One fix against the truth at its frame (map_fixes.csv).
struct MapFixRow {
  int64_t utime = 0;
  double error_north_m = 0, error_east_m = 0;
  double sigma_north_m = 0, sigma_east_m = 0;
  double mahalanobis = 0;
  double score = 0, peak_ratio = 0, search_radius_m = 0, gsd_m = 0;
};

struct MapFixMetrics {
  int64_t fixes = 0;             // MAP_FIX messages with truth at their frame
  int64_t applied = 0;           // poses flagged FLAG_MAP_FIX_APPLIED
  int64_t rejected = 0;          // poses flagged FLAG_MAP_FIX_REJECTED
  double error_median_m = 0, error_p95_m = 0, error_max_m = 0;  // horizontal, fix vs truth
  double sigma_median_m = 0;     // sqrt of the larger eigenvalue of the fix covariance
  double mahalanobis_max = 0;    // of the error against the fix's own covariance
  int64_t beyond_3_sigma = 0;    // fixes whose Mahalanobis distance exceeds 3
  std::vector<MapFixRow> rows;
};

// map_fixes.csv: one row per fix (nothing written without fixes).
void write_map_fixes_csv(const MapFixMetrics& m, const std::string& path);

// `first` / `truth0`: the pose and truth the trajectory is aligned at.
MapFixMetrics map_fix_metrics(const std::vector<map_fix_t>& fixes, const std::vector<pose_t>& poses,
                              const std::vector<ground_truth_t>& truth, const pose_t& first, const TruthAt& truth0);

}  // namespace nadir
