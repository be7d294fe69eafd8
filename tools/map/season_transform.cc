#include "tools/map/season_transform.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nadir::map {

void SeasonTransform::Check() const {
  double previous = 0.0;
  for (const LandCoverClass& c : classes) {
    if (!(c.albedo_below > previous))
      throw std::invalid_argument("season class " + c.name + ": albedo_below must increase from class to class");
    if (!(c.contrast > 0.0 && c.contrast <= 2.0))
      throw std::invalid_argument("season class " + c.name + ": contrast must be in (0, 2]");
    if (!(c.gamma > 0.2 && c.gamma <= 5.0))
      throw std::invalid_argument("season class " + c.name + ": gamma must be in (0.2, 5]");
    if (!(std::fabs(c.brightness) <= 0.5))
      throw std::invalid_argument("season class " + c.name + ": brightness must be in [-0.5, 0.5]");
    previous = c.albedo_below;
  }
  if (!(classes[2].albedo_below > 255.0)) throw std::invalid_argument("season class bright must reach albedo 255");
  if (!(sun_elevation_deg > 5.0 && sun_elevation_deg <= 90.0))
    throw std::invalid_argument("season sun_elevation_deg must be in (5, 90]");
  if (!(ambient >= 0.0 && ambient <= 1.0)) throw std::invalid_argument("season ambient must be in [0, 1]");
}

const LandCoverClass& SeasonTransform::land_cover(double albedo) const {
  for (const LandCoverClass& c : classes)
    if (albedo < c.albedo_below) return c;
  return classes[2];
}

uint8_t SeasonTransform::apply(double albedo, double dh_dn, double dh_de) const {
  const LandCoverClass& c = land_cover(albedo);
  double v = 0.5 + c.contrast * (albedo / 255.0 - 0.5) + c.brightness;
  v = std::pow(std::clamp(v, 0.0, 1.0), c.gamma);
  const double az = sun_azimuth_deg * M_PI / 180.0, el = sun_elevation_deg * M_PI / 180.0;
  const double sn = std::cos(el) * std::cos(az), se = std::cos(el) * std::sin(az), su = std::sin(el);
  const double norm = std::sqrt(dh_dn * dh_dn + dh_de * dh_de + 1.0);
  const double shade = std::max(ambient, (-dh_dn * sn - dh_de * se + su) / (norm * su));
  return static_cast<uint8_t>(std::lround(std::clamp(255.0 * v * shade, 0.0, 255.0)));
}

}  // namespace nadir::map
