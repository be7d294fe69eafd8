#pragma once
// Where a Terrain's ground comes from when it is not the procedural world:
// a height field and an albedo over the local north/east plane (metres from
// the start point), e.g. an orthophoto and a DEM of a real place
// (tools/map/raster_ground.h). The Terrain samples it on its 1 m grid and
// caches it exactly as it does the procedural field, so the renderer,
// altimeter and ground truth all see the same surface.
//
// A source is immutable after construction and called from one thread at a
// time (a Terrain is not thread-safe either). Its calls may throw (e.g. a
// NoData pixel): the error reaches whoever asked the Terrain.

#include <string>

namespace nadir::sim {

// Bounds a ray caster can trust, valid for every (north, east).
struct GroundBounds {
  double min_height = 0.0, max_height = 0.0;  // of height()
  // Lipschitz bound of height(): |h(p) - h(q)| <= max_slope * |p - q| for any
  // two points (dimensionless, rise over run).
  double max_slope = 0.0;
};

class GroundSource {
 public:
  virtual ~GroundSource() = default;
  // Height above the datum (m, up positive); height(0, 0) == 0.
  virtual double height(double north, double east) const = 0;
  // Ground albedo 0..255 (grey value), point-sampled.
  virtual float albedo(double north, double east) const = 0;
  virtual GroundBounds bounds() const = 0;
  // A short name for messages and CONFIG (e.g. the files it reads).
  virtual std::string describe() const = 0;
};

}  // namespace nadir::sim
