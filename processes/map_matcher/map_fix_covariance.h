#pragma once
// The covariance (north, east; m^2) of a map fix.
//
// Peak: for a template matched by normalised cross-correlation the shift's
// covariance behaves like (1 - rho) / rho * (-H)^-1 / N (rho the peak
// score, H the surface's Hessian at the peak per px^2, N the independent
// samples: template pixels over the lobe's pixels). The misfit between a map
// and a frame (another season, moved shadows, changed patches, relief) is
// not white noise, so this is scaled by peak_stddev_scale^2 (measured on
// simulated maps, docs/maps.md) and floored at min_stddev_px per axis. In
// pixels of (column = east, row = south), then turned to (north, east) metres.
// Added, each horizontal axis: the map's georeferencing error and the ground
// shift an attitude error makes at this height.

#include <Eigen/Core>

#include "processes/map_matcher/map_matcher_options.h"
#include "processes/map_matcher/map_registration.h"

namespace nadir {

// False when the peak is not a maximum (H not negative definite).
bool map_fix_covariance(const MapMatcherOptions& options, const Registration& registration, int template_pixels,
                        double height_m, Eigen::Matrix2d* covariance_ne);

}  // namespace nadir
