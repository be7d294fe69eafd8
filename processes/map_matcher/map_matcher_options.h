#pragma once
// Options of the map matcher (the `map_matcher:` section of the config),
// documented where they are read (map_matcher_options.cc). Check() throws
// ConfigError naming the key.

#include <string>

#include "common/config.h"
#include "common/options_schema.h"

namespace nadir {

struct MapMatcherOptions {
  // The reference map: an orthophoto and a DEM (GeoTIFF or any raster GDAL
  // reads, any CRS; tools/map/reference_map.h). Relative paths resolve from
  // the checkout. Both are required to run the matcher.
  std::string orthophoto;
  std::string dem;
  double gsd_m = 1.0;             // the frames and the map are compared at this ground sample distance
  double interval_s = 1.0;        // at most one fix attempt per this much sensor time
  double max_frame_age_s = 1.0;   // a frame whose POSE has not come within this is dropped
  double template_fraction = 0.9; // of the largest north-up square the frame's footprint holds at any heading
  int min_template_px = 32;       // a smaller template (low flight, coarse gsd) is not matched
  // Search radius: this many horizontal prior sigmas (wide enough that the
  // truth lies inside with overwhelming probability, so that a copy of the
  // ground inside the search cannot pass for the only fit when the truth is
  // just outside it) ...
  double search_sigmas = 5.0;
  double min_search_radius_m = 10.0;   // ... but at least this ...
  double max_search_radius_m = 200.0;  // ... and a prior needing more is refused (too uncertain)
  double min_texture = 6.0;       // grey-level stddev of the map window and of the frame; below: featureless
  // Mean edge strength (gradient magnitude, grey levels per pixel at gsd_m)
  // of the map window and of the frame; below: featureless.
  double min_edge_strength = 2.0;
  double min_score = 0.3;         // normalised cross-correlation of the edge pictures at the peak; below: no match
  double min_peak_ratio = 1.5;    // best peak over its best rival; below: ambiguous
  double max_fix_stddev_m = 5.0;  // a peak so flat that the fix's larger sigma exceeds this: ambiguous
  // The map's own ground at the fix correlated with the rest of the search
  // window: its best rival over this, the map repeats itself there.
  double max_map_self_similarity = 0.6;
  // Covariance of a fix (map_fix_covariance.h): the peak's shape, the
  // inverse Hessian of the correlation surface, times (1 - score) / score
  // over the number of independent peak-sized cells in the template, times
  // peak_stddev_scale^2 (the misfit between map and frame is not white
  // noise), at least min_stddev_px; plus the map's own error that differs
  // from fix to fix (map_stddev_m; the error common to all its fixes is yaw
  // fusion's map_fix.systematic_stddev_m) and the attitude error projected
  // on the ground (height x attitude_stddev_deg).
  double peak_stddev_scale = 6.0;
  double min_stddev_px = 0.15;
  double map_stddev_m = 0.3;
  double attitude_stddev_deg = 0.05;
  // The INS's roll/pitch sigma as the config describes the sensors
  // (vo_solver.uncertainty: its white and correlated parts combined), set by
  // from_config: the fix's attitude term uses the larger of the two, so a
  // noisier INS described there is not forgotten here.
  double ins_attitude_stddev_deg = 0.0;
  double max_tilt_deg = 20.0;     // frames tilted further from nadir are not matched
  // The DEM's error at a point (m, 1 sigma), published with each fix's ground
  // height (MAP_FIX.ground_down_variance): set it to your DEM's vertical
  // accuracy. What all its heights share (its datum) is yaw fusion's
  // map_fix.systematic_vertical_stddev_m.
  double dem_stddev_m = 0.5;

  static MapMatcherOptions from_config(const Config& root);
  void Check() const;  // throws ConfigError naming the key and allowed range
  static const OptionsSchema<MapMatcherOptions>& schema();
};

}  // namespace nadir
