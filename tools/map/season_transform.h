#pragma once
// The "other season and light" of the simulated reference map: how a map
// pixel's grey value follows from the ground albedo the simulator's camera
// sees, so that the map resembles the world the way a real orthophoto flown
// in another season does, without being it.
//
// Land cover: the simulator's Terrain exposes no classes, only an albedo, so
// the cover is taken from the albedo band of the pixel (averaged over its
// footprint):
//   dark    albedo <  75   trees, hedges, dark soil   -> winter: bare, lighter, flatter
//   field   75 .. 185      fields and meadows          -> stubble: lighter, less contrast
//   bright  albedo >= 185  roads, rocks, bare ground   -> a little darker (wet)
// Per class, with v = albedo / 255:
//   v' = clamp(0.5 + contrast * (v - 0.5) + brightness, 0, 1) ^ gamma
// Light: a hillshade with the map's own sun (default from the south-west,
// azimuth 225 deg, 35 deg up; the simulator's renderer lights from the
// south-east, azimuth 135 deg, 50 deg up), normalised like the renderer's so
// that flat ground is 1, never below `ambient`:
//   shade = max(ambient, (-dh/dn * s_n - dh/de * s_e + s_u) / (|(-dh/dn, -dh/de, 1)| * s_u))
// so slopes lit in the camera's images are shaded in the map and vice versa.
//   pixel = round(clamp(255 * v' * shade, 0, 255))

#include <cstdint>
#include <string>

namespace nadir::map {

struct LandCoverClass {
  std::string name;
  double albedo_below = 256.0;  // the class holds albedo < this (and >= the previous class's)
  double brightness = 0.0;      // added to v (0..1)
  double contrast = 1.0;        // about v = 0.5
  double gamma = 1.0;
};

struct SeasonTransform {
  LandCoverClass classes[3] = {
      {"dark", 75.0, 0.12, 0.6, 0.85},
      {"field", 185.0, 0.06, 0.7, 1.15},
      {"bright", 256.0, -0.06, 0.9, 1.0},
  };
  double sun_azimuth_deg = 225.0;  // clockwise from north
  double sun_elevation_deg = 35.0;
  double ambient = 0.3;  // the darkest a slope turned from the sun gets

  // Throws std::invalid_argument naming the field out of range.
  void Check() const;
  const LandCoverClass& land_cover(double albedo) const;
  // Grey value 0..255 of a pixel with mean albedo `albedo` on ground of
  // gradient (dh/dnorth, dh/deast).
  uint8_t apply(double albedo, double dh_dn, double dh_de) const;
};

}  // namespace nadir::map
