#pragma once
// One fix attempt, without a bus: a camera frame, the POSE of that frame as
// the prior, the reference map -> an absolute horizontal fix with the DEM's
// ground height under it, or the reason it is refused.
//
// The frame is orthorectified (frame_ortho.h) over a north-up square below
// the prior position, using the pose's attitude, its height above ground
// and the map's DEM for the relief; the square is searched for in the map's
// orthophoto within search_sigmas horizontal prior sigmas
// (map_registration.h). A fix is refused, never guessed, when:
//   no_height        the pose has no height above ground
//   tilted           the frame looks further than max_tilt_deg from nadir
//   prior_uncertain  the search would need a radius over max_search_radius_m
//   template_small   the square is under min_template_px at gsd_m (flying low)
//   outside_map      the prior's window reaches beyond the orthophoto or the DEM
//   map_no_data      NoData (or NaN) in the window or under the frame
//   frame_partial    the frame does not see the whole square
//   featureless      the map window or the frame has a grey stddev under
//                    min_texture, or a mean edge strength under min_edge_strength
//                    (a weak texture, or only the smooth shading of relief)
//   low_score        the correlation peak is under min_score
//   ambiguous        another shift fits nearly as well (peak_ratio under
//                    min_peak_ratio: repetitive ground) or the peak is flat
//   peak_at_edge     the best shift is on the border of the search
//   repetitive       the map repeats itself within the search: its own ground
//                    at the fix fits elsewhere in the window with a correlation
//                    over max_map_self_similarity (rows of fields, a copy)
// The fix's covariance: map_fix_covariance.h.

#include <Eigen/Core>

#include <memory>
#include <string>

#include "common/camera_model.h"
#include "nadir/image_t.hpp"
#include "nadir/map_fix_t.hpp"
#include "nadir/pose_t.hpp"
#include "processes/map_matcher/map_matcher_options.h"
#include "tools/map/map_grid.h"
#include "tools/map/reference_map.h"

namespace nadir {

enum class FixRefusal {
  kNone = 0,
  kNoHeight,
  kTilted,
  kPriorUncertain,
  kTemplateSmall,
  kOutsideMap,
  kMapNoData,
  kFramePartial,
  kFeatureless,
  kLowScore,
  kAmbiguous,
  kPeakAtEdge,
  kRepetitive,
  kFrameDropped,  // the node's: the frame's POSE did not come in time, or a bad image
};
constexpr int kFixRefusals = 14;
const char* fix_refusal_name(FixRefusal refusal);

struct FixAttempt {
  FixRefusal refusal = FixRefusal::kNone;
  std::string why;  // names the figure and its limit when refused
  map_fix_t fix{};  // filled when accepted (and its diagnostics as far as they got when refused)
  // Diagnostics as far as the attempt got (-1: not reached).
  double frame_edge_strength = -1.0, map_edge_strength = -1.0;
  double map_self_similarity = -1.0;
};

class MapMatcher {
 public:
  // Checks the options (ConfigError naming the key). `camera_lever_arm_m`:
  // the camera centre from the INS reference point (body frame, camera.lever_arm_m).
  MapMatcher(const MapMatcherOptions& options, const CameraModel& camera, map::ReferenceMap map,
             const Eigen::Vector3d& camera_lever_arm_m = Eigen::Vector3d::Zero());

  // `origin`: where the POSE origin (local north/east 0, 0) lies on the
  // Earth, its height that of POSE's down 0.
  FixAttempt attempt(const image_t& image, const pose_t& pose, const map::LocalProjection& origin) const;

  const map::ReferenceMap& map() const { return map_; }
  const MapMatcherOptions& options() const { return options_; }

 private:
  // The DEM's ground at the fix's position (MAP_FIX.ground_*); left as it is
  // (no height) where the DEM ends or has NoData.
  void set_ground(const map::LocalProjection& origin, map_fix_t* fix) const;

  MapMatcherOptions options_;
  CameraModel camera_;
  map::ReferenceMap map_;
  Eigen::Vector3d camera_lever_arm_m_;
};

}  // namespace nadir
