#pragma once
// The image scale against GNSS: the ratio of the GNSS horizontal baseline to
// the VO horizontal step over the solved frame pairs of a segment. A VO step
// is proportional to range / focal length, so a ratio other than 1 is the
// combined error of the focal length (an undocumented camera) and the height
// (a barometric height, an altimeter scale): neither can be told apart from
// the other here, and the user says which one to correct.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace nadir::calibrate {

struct VoStep {
  int64_t prev_utime = 0, utime = 0;
  double dx = 0, dy = 0;  // horizontal step in the level frame of the previous frame (m)
  int32_t quality = 0;
};

struct PositionSample {
  int64_t utime = 0;
  Eigen::Vector3d position_ned = Eigen::Vector3d::Zero();
  double yaw = 0.0;  // the recorded yaw (rad): the heading the VO steps are turned by
};

struct GpsScaleFit {
  double scale = 1.0;   // GNSS baseline / VO step (median over the pairs used)
  double sigma = 0.0;   // 1-sigma of that median (robust spread / sqrt(n), for pairs of independent errors)
  int64_t pairs = 0;    // pairs used
  int64_t rejected = 0; // solved pairs outside min_baseline_m or beyond outlier_sigma robust sigmas
};

// `positions` sorted by utime (GNSS positions, e.g. the INS's). Steps whose
// quality has any bit of `unsolved_mask` are skipped, so are pairs whose GNSS
// baseline is under `min_baseline_m` or that the positions do not cover.
// Returns pairs == 0 when nothing is usable.
GpsScaleFit fit_gps_scale(const std::vector<VoStep>& steps, const std::vector<PositionSample>& positions,
                          int32_t unsolved_mask, double min_baseline_m, double outlier_sigma);

// The steady offset between the recorded yaw and the images' heading (a
// compass disturbed by the site, a gimbal yaw offset): per solved pair, the
// GNSS baseline's direction minus the VO step's turned by the recorded yaw
// at the previous frame; the median over the pairs, outliers dropped as in
// fit_gps_scale. Image heading = recorded yaw + offset.
struct HeadingOffsetFit {
  double offset_rad = 0.0;
  double sigma_rad = 0.0;  // 1-sigma of the median (robust spread / sqrt(n))
  int64_t pairs = 0;
  int64_t rejected = 0;
};
HeadingOffsetFit fit_heading_offset(const std::vector<VoStep>& steps, const std::vector<PositionSample>& positions,
                                    int32_t unsolved_mask, double min_baseline_m, double outlier_sigma);

}  // namespace nadir::calibrate
