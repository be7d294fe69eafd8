#pragma once
// First intersection of a ray with the height field.
// f(t) = altitude of the ray point - terrain height below it. When the ray is
// steeper than the terrain can ever be (dz > max_slope * |d_horizontal|), f is
// strictly decreasing, the root is unique and a safeguarded Newton solve finds
// it. Otherwise relief can occlude: the ray walks the terrain's 64 m tiles,
// skipping those whose highest point stays below it and sphere-tracing the
// others with steps that cannot pass a surface under the tile's own slope
// bound (f / (dz + slope_tile * |d_h|)), so the first hit wins.

#include <Eigen/Core>

#include "processes/sim/terrain.h"

namespace nadir::sim {

struct RayHit {
  double t = 0.0;            // distance along the (unit) direction
  double dh_dn = 0.0, dh_de = 0.0;  // terrain gradient at the hit
  bool marched = false;      // took the occlusion-safe path
};

// origin in NED (m), dir a unit NED vector. t_guess <= 0: no guess.
// Returns false when the ray does not reach the ground (looking up, origin below ground).
bool cast_ray(const Terrain& terrain, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_guess,
              RayHit* hit);

}  // namespace nadir::sim
