#include "processes/sim/featureless_area.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace nadir::sim {
namespace {

void require(bool ok, const std::string& key, const std::string& field, const std::string& what) {
  if (!ok) throw std::invalid_argument("key '" + key + "." + field + "' " + what);
}

std::string range_text(double value, double lo, double hi) {
  std::ostringstream text;
  text << "= " << value << " is out of range [" << lo << ", " << hi << "]";
  return text.str();
}

std::string pair_text(double a, double b) {
  std::ostringstream text;
  text << "= [" << a << ", " << b << "] must be [min, max] with min < max";
  return text.str();
}

}  // namespace

void FeaturelessArea::Check(const std::string& key) const {
  require(std::isfinite(north_min_m) && std::isfinite(north_max_m) && north_min_m < north_max_m, key, "north_m",
          pair_text(north_min_m, north_max_m));
  require(std::isfinite(east_min_m) && std::isfinite(east_max_m) && east_min_m < east_max_m, key, "east_m",
          pair_text(east_min_m, east_max_m));
  require(contrast >= 0.0 && contrast <= 1.0, key, "contrast", range_text(contrast, 0.0, 1.0));
  require(shore_m >= 0.0 && shore_m <= 1e5, key, "shore_m", range_text(shore_m, 0.0, 1e5));
  require(albedo >= 8.0 && albedo <= 250.0, key, "albedo", range_text(albedo, 8.0, 250.0));
}

FeaturelessGround::FeaturelessGround(const std::vector<FeaturelessArea>& areas) : areas_(areas) {
  if (areas_.empty()) return;
  north_min_ = east_min_ = 1e300;
  north_max_ = east_max_ = -1e300;
  for (const FeaturelessArea& a : areas_) {
    north_min_ = std::min(north_min_, a.north_min_m - a.shore_m);
    north_max_ = std::max(north_max_, a.north_max_m + a.shore_m);
    east_min_ = std::min(east_min_, a.east_min_m - a.shore_m);
    east_max_ = std::max(east_max_, a.east_max_m + a.shore_m);
  }
}

double FeaturelessGround::contrast_at(const FeaturelessArea& area, double north, double east) {
  const double dn = std::max({area.north_min_m - north, 0.0, north - area.north_max_m});
  const double de = std::max({area.east_min_m - east, 0.0, east - area.east_max_m});
  if (dn == 0.0 && de == 0.0) return area.contrast;
  const double d = std::hypot(dn, de);
  if (d >= area.shore_m) return 1.0;
  const double s = d / area.shore_m;
  return area.contrast + (1.0 - area.contrast) * s * s * (3.0 - 2.0 * s);
}

float FeaturelessGround::apply_inside(double north, double east, float albedo) const {
  double value = albedo;
  bool changed = false;
  for (const FeaturelessArea& a : areas_) {
    const double k = contrast_at(a, north, east);
    if (k >= 1.0) continue;
    value = a.albedo + k * (value - a.albedo);
    changed = true;
  }
  // Between the level and the ground's own (clamped) albedo: no clamp needed.
  return changed ? static_cast<float>(value) : albedo;
}

}  // namespace nadir::sim
