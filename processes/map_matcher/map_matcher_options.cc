#include "processes/map_matcher/map_matcher_options.h"

#include <cmath>

#include "common/delta_uncertainty_options.h"

namespace nadir {

const OptionsSchema<MapMatcherOptions>& MapMatcherOptions::schema() {
  using O = MapMatcherOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("map_matcher",
                       "Registers camera frames against a reference map (orthophoto + DEM) around the fused pose "
                       "and publishes absolute fixes on MAP_FIX (horizontal, with the DEM's ground under them); refuses what it cannot trust.");
    s.text("orthophoto", "reference orthophoto (GeoTIFF, any CRS); relative to the checkout", &O::orthophoto)
        .text("dem", "DEM of heights above the WGS84 ellipsoid (GeoTIFF, any CRS); relative to the checkout",
              &O::dem)
        .number("gsd_m", 0.1, 10.0, "m", "ground sample distance frames and map are compared at", &O::gsd_m)
        .number("interval_s", 0.0, 3600.0, "s", "at most one fix attempt per this much sensor time", &O::interval_s)
        .number("max_frame_age_s", 0.05, 30.0, "s", "a frame whose POSE has not come within this is dropped",
                &O::max_frame_age_s)
        .number("template_fraction", 0.1, 1.0, "",
                "template side: this fraction of the largest north-up square inside the footprint at any heading",
                &O::template_fraction)
        .number("min_template_px", 8, 4096, "px", "a smaller template is not matched", &O::min_template_px)
        .number("search_sigmas", 1.0, 10.0, "", "search radius in horizontal prior sigmas", &O::search_sigmas)
        .number("min_search_radius_m", 0.0, 1000.0, "m", "the search radius is at least this",
                &O::min_search_radius_m)
        .number("max_search_radius_m", 1.0, 5000.0, "m", "a prior needing a larger search is refused",
                &O::max_search_radius_m)
        .number("min_texture", 0.0, 128.0, "grey levels", "map window or frame with a smaller stddev: featureless",
                &O::min_texture)
        .number("min_edge_strength", 0.0, 255.0, "grey levels/px",
                "map window or frame with a smaller mean gradient magnitude: featureless", &O::min_edge_strength)
        .number("min_score", -1.0, 1.0, "", "normalised cross-correlation at the peak; below: no match",
                &O::min_score)
        .number("min_peak_ratio", 1.0, 100.0, "", "best peak over its best rival (the highest local maximum beyond its half-peak radius); below: ambiguous",
                &O::min_peak_ratio)
        .number("max_fix_stddev_m", 0.01, 1000.0, "m", "a fix whose larger sigma exceeds this is refused (flat peak)",
                &O::max_fix_stddev_m)
        .number("max_map_self_similarity", -1.0, 1.0, "",
                "the map's ground at the fix fits elsewhere in the search better than this: repetitive",
                &O::max_map_self_similarity)
        .number("peak_stddev_scale", 0.01, 1000.0, "", "scales the sigma the correlation peak's shape gives",
                &O::peak_stddev_scale)
        .number("min_stddev_px", 0.0, 100.0, "px", "floor on the peak's sigma, each axis", &O::min_stddev_px)
        .number("map_stddev_m", 0.0, 100.0, "m", "the map's error that differs from fix to fix, each horizontal axis (its error common to all fixes: yaw_fusion.map_fix.systematic_stddev_m)",
                &O::map_stddev_m)
        .number("attitude_stddev_deg", 0.0, 10.0, "deg",
                "roll/pitch error projected on the ground; the INS's described in vo_solver.uncertainty "
                "(roll_pitch_stddev_deg and roll_pitch_correlated_stddev_deg combined) when that is larger",
                &O::attitude_stddev_deg)
        .number("max_tilt_deg", 0.0, 60.0, "deg", "frames tilted further from nadir are not matched",
                &O::max_tilt_deg)
        .number("dem_stddev_m", 0.01, 100.0, "m",
                "the DEM's error at a point, published with each fix's ground height (its error common to all "
                "heights: yaw_fusion.map_fix.systematic_vertical_stddev_m)",
                &O::dem_stddev_m)
        .rule("max_search_radius_m", [](const O& o) { return o.max_search_radius_m >= o.min_search_radius_m; },
              "must be at least min_search_radius_m");
    return s;
  }();
  return schema;
}

MapMatcherOptions MapMatcherOptions::from_config(const Config& root) {
  MapMatcherOptions options = schema().read(root.section_or_empty("map_matcher"));
  const DeltaUncertaintyOptions ins = DeltaUncertaintyOptions::from_config(root.section_or_empty("vo_solver"));
  options.ins_attitude_stddev_deg = std::hypot(ins.roll_pitch_stddev_deg, ins.roll_pitch_correlated_stddev_deg);
  return options;
}

void MapMatcherOptions::Check() const { schema().check(*this); }

}  // namespace nadir
