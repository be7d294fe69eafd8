#include "processes/sim/ray_caster.h"

#include <algorithm>
#include <cmath>

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
    // Occlusion possible: sphere-trace from where the ray enters the relief band.
    hit->marched = true;
    t = t_lo0;
    double ft = f(t);
    if (ft < 0) return false;  // origin inside the terrain
    for (int i = 0; i < 2000 && ft > 1e-3; ++i) {
      t += ft / (dz + slope * dxy);
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
