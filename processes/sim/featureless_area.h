#pragma once
// Featureless ground (calm water, snow, sand, bare flats) cut into the
// simulated terrain: inside an area's box the albedo keeps only `contrast` of
// its deviation from the area's constant level, so fields, hedges, roads and
// trees fade to a weak texture the tracker may still follow but a map matcher
// should not trust (a normalised correlation is blind to the scale of the
// deviation: what is lost is texture against the camera's noise and 8-bit
// levels). The level is a constant rather than a smoothed regional mean, so
// nothing of the ground's layout at any scale survives but the weakened
// deviation. Outside the box a shore band of width `shore_m` blends back to
// full contrast (smoothstep of the distance to the box), so the shore is a
// gradual change, not a hard edge. Heights, and so the relief's shading, are
// not changed. The result is a pure function of (areas, north, east), like
// the rest of the terrain.

#include <string>
#include <vector>

namespace nadir::sim {

struct FeaturelessArea {
  // Box in local metres from the profile's reference point (the start),
  // where the contrast is fully cut: north_m: [north_min, north_max] etc.
  double north_min_m = 0.0, north_max_m = 0.0;
  double east_min_m = 0.0, east_max_m = 0.0;
  double contrast = 0.08;  // 0..1: fraction of the albedo's deviation kept (0: uniform level)
  double shore_m = 100.0;  // >= 0: width of the blend to full contrast, outside the box
  double albedo = 128.0;   // 8..250: the level the deviation is taken from (water: darker)

  // Throws std::invalid_argument "key 'KEY.contrast' ..." naming the bad
  // field under `key` (e.g. terrain.featureless[0]).
  void Check(const std::string& key) const;
};

// A set of areas applied to albedo values, with a bounding box of every
// area and its shore band so points outside cost one comparison chain.
class FeaturelessGround {
 public:
  explicit FeaturelessGround(const std::vector<FeaturelessArea>& areas);

  bool empty() const { return areas_.empty(); }
  // The albedo at (north, east) given the ground's own albedo there: `albedo`
  // itself (bit for bit) outside every area and shore band. Overlapping
  // areas compound.
  float apply(double north, double east, float albedo) const {
    if (areas_.empty() || north < north_min_ || north > north_max_ || east < east_min_ || east > east_max_)
      return albedo;
    return apply_inside(north, east, albedo);
  }
  // Fraction of the deviation kept at a point for one area: `contrast` in the
  // box, rising to 1 across the shore band.
  static double contrast_at(const FeaturelessArea& area, double north, double east);

 private:
  float apply_inside(double north, double east, float albedo) const;

  std::vector<FeaturelessArea> areas_;
  double north_min_ = 0.0, north_max_ = 0.0, east_min_ = 0.0, east_max_ = 0.0;
};

}  // namespace nadir::sim
