#pragma once
// A real place as the simulator's ground: the orthophoto and DEM a flight
// profile names (`world: {orthophoto: FILE, dem: FILE}`), read with the map
// matcher's reader (reference_map.h: any CRS, NoData never read as a value)
// and laid on the simulator's local north/east plane around the profile's
// reference point (LocalProjection, map_grid.h).
//
// Datum: the DEM's ellipsoidal height at the reference point. Heights are
// DEM - datum, so height(0, 0) == 0 as for the procedural world, and the
// profile's reference height becomes that datum (attach_raster_world), which
// keeps the truth's ellipsoidal heights those of the DEM.
// Albedo: the orthophoto's grey value (bilinear, point-sampled).
//
// Coverage: the world is the local box the flight can see (its track widened
// by the view margin below); attach_raster_world refuses a flight whose box
// reaches outside either raster, or whose track crosses NoData, with an error
// naming the file. Points beyond the box (cache tiles at its edges, never in
// view) take the box edge's value; NoData inside it throws MapNoDataError
// naming the file when asked for -- never a silent zero.
//
// Bounds (GroundSource::bounds): the DEM's lowest and highest heights and a
// slope bound from its largest pixel-to-pixel step over the shortest ground
// size of a pixel, over the whole DEM, so the ray caster can trust them.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "processes/sim/flight_profile.h"
#include "processes/sim/ground_source.h"
#include "tools/map/map_grid.h"
#include "tools/map/reference_map.h"

namespace nadir::map {

// A box of local north/east metres.
struct LocalBox {
  double north_min = 0.0, north_max = 0.0, east_min = 0.0, east_max = 0.0;
};

// Over a whole DEM (ellipsoidal metres): its lowest and highest heights, and
// a Lipschitz bound of its bilinear surface (rise over run): the largest
// height step between neighbouring pixels, in pixel units, over the smallest
// ground size of a pixel (singular value of the pixel-to-ground map, sampled
// on a 9 x 9 lattice), with 5 % to spare for the local plane's scale.
struct DemBounds {
  double min_height = 0.0, max_height = 0.0, max_slope = 0.0;
};
// Reads the DEM band row by row; throws MapError naming the file.
DemBounds read_dem_bounds(const std::string& dem_path);

class RasterGround : public sim::GroundSource {
 public:
  // Takes the opened pair and its DEM's bounds; `latitude_deg`,
  // `longitude_deg`: the local origin. Throws MapError naming the file when
  // the box is not covered by both rasters, or the DEM has no height at the
  // origin.
  RasterGround(ReferenceMap map, const DemBounds& dem, double latitude_deg, double longitude_deg, const LocalBox& box);

  double height(double north, double east) const override;
  float albedo(double north, double east) const override;
  sim::GroundBounds bounds() const override { return bounds_; }
  std::string describe() const override;

  // Ellipsoidal height (m) of the datum: the DEM at the origin.
  double datum_height_m() const { return datum_; }
  const LocalBox& box() const { return box_; }
  const ReferenceMap& map() const { return map_; }

 private:
  // Geodetic point of a local one, clamped into the box, from the node lattice.
  void geodetic(double north, double east, double* latitude_deg, double* longitude_deg) const;

  ReferenceMap map_;
  LocalBox box_;
  double datum_ = 0.0;
  sim::GroundBounds bounds_;
  // Latitude/longitude exact at nodes every step_ metres over the box,
  // bilinear in between (sub-millimetre at this scale).
  double step_ = 32.0;
  int nodes_n_ = 0, nodes_e_ = 0;
  std::vector<Eigen::Vector2d> nodes_;
};

// The view margin (m) around an aircraft `height_above_ground_m` above the
// lowest ground: what a camera of up to ~110 degrees diagonal field of view
// sees banked (1.5 x the height, plus 100 m).
double view_margin_m(double height_above_ground_m);

// Opens the world `profile` names (profile->has_world()), checks it holds the
// flight of `seed` (the trajectory's track every 0.5 s, each point widened by
// the view margin; NoData under the track) and makes it the profile's ground:
// sets profile->terrain.ground and profile->reference_height_m (the datum).
// Throws MapError naming the file and, for a flight leaving a raster, the
// time and place it does.
void attach_raster_world(sim::FlightProfile* profile, uint64_t seed);

}  // namespace nadir::map
