#include "processes/sim/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace nadir::sim {

bool cast_ray(const Terrain& terrain, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_guess,
              RayHit* hit) {
  const double dz = dir.z();  // down component: positive when descending
  if (dz <= 1e-6) return false;
  const double altitude = -origin.z();
  const double dxy = std::hypot(dir.x(), dir.y());
  const double slope = terrain.max_slope();
  double gn = 0, ge = 0;
  auto f = [&](double t) {
    return altitude - t * dz - terrain.height(origin.x() + t * dir.x(), origin.y() + t * dir.y(), &gn, &ge);
  };
  const double t_lo0 = std::max(0.0, (altitude - terrain.max_height()) / dz);
  const double t_hi0 = (altitude - terrain.min_height()) / dz;
  if (t_hi0 <= 0.0) return false;
  hit->marched = false;

  double lo = t_lo0, hi = t_hi0;
  double t;
  if (slope * dxy < dz) {
    t = (t_guess > lo && t_guess < hi) ? t_guess : 0.5 * (lo + hi);
  } else {
    // Occlusion possible: walk the tiles the ray crosses from where it enters
    // the relief band. A tile whose highest sample stays below the ray is
    // skipped whole; in the others the ray is sphere-traced with steps that
    // cannot pass a surface under that tile's own slope bound
    // (f / (dz + slope_tile * |d_h|)), cut at the tile's edge, where the next
    // tile's bounds take over. So the first hit wins, in few steps.
    hit->marched = true;
    t = t_lo0;
    double ft = f(t);
    if (ft < 0) return false;  // origin inside the terrain
    constexpr double kTile = Terrain::kBoundsTileM;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    // Past a tile edge by a micrometre, so the next point lies in the next
    // tile (a root skipped by that much is still bracketed below).
    constexpr double kEdgeNudge = 1e-6;
    for (int i = 0; i < 4000 && ft > 1e-3; ++i) {
      const double pn = origin.x() + t * dir.x(), pe = origin.y() + t * dir.y();
      const double tile_n = std::floor(pn / kTile), tile_e = std::floor(pe / kTile);
      const HeightBounds b = terrain.tile_bounds(static_cast<int32_t>(tile_n), static_cast<int32_t>(tile_e));
      double t_exit = kInf;
      if (dir.x() > 0) t_exit = std::min(t_exit, ((tile_n + 1.0) * kTile - origin.x()) / dir.x());
      if (dir.x() < 0) t_exit = std::min(t_exit, (tile_n * kTile - origin.x()) / dir.x());
      if (dir.y() > 0) t_exit = std::min(t_exit, ((tile_e + 1.0) * kTile - origin.y()) / dir.y());
      if (dir.y() < 0) t_exit = std::min(t_exit, (tile_e * kTile - origin.y()) / dir.y());
      t_exit = std::max(t_exit, t) + kEdgeNudge;
      if (t_exit < kInf && altitude - t_exit * dz > b.max_height) {
        t = t_exit;  // above everything in this tile
      } else {
        const double t_top = (altitude - b.max_height) / dz;  // where the ray sinks to the tile's top
        if (t_top > t) {
          t = t_top;
        } else {
          t = std::min(t + ft / (dz + b.max_slope * dxy), t_exit);
        }
      }
      if (t > t_hi0) return false;
      ft = f(t);
    }
    lo = t - 0.01;
    hi = std::min(t_hi0, t + 0.01 + std::fabs(ft));
  }
  // Safeguarded Newton in [lo, hi] (f(lo) >= 0 >= f(hi) on the first root's side).
  for (int i = 0; i < 60; ++i) {
    const double ft = f(t);
    if (ft > 0) lo = t; else hi = t;
    const double dft = -dz - gn * dir.x() - ge * dir.y();
    double next = (dft < 0) ? t - ft / dft : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double step = std::fabs(next - t);
    t = next;
    if (step < 2e-3) {
      // Newton from within 2 mm lands within micrometres; refresh the gradient.
      f(t);
      break;
    }
  }
  hit->t = t;
  hit->dh_dn = gn;
  hit->dh_de = ge;
  return true;
}

}  // namespace nadir::sim
