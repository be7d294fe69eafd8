#include "tools/import/working_resolution.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace nadir::import {

WorkingResolution working_resolution(int width, int height, double requested) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("working_resolution: image size must be > 0");
  WorkingResolution r;
  const int long_side = std::max(width, height);
  char text[160];
  if (requested > 0.0) {
    r.scale = requested;
    std::snprintf(text, sizeof(text), "%g: --scale", requested);
  } else {
    const int k = (long_side + kWorkingLongSidePx - 1) / kWorkingLongSidePx;  // ceil, >= 1
    r.scale = 1.0 / k;
    if (k == 1) {
      std::snprintf(text, sizeof(text), "1: long side %d px within %d px", long_side, kWorkingLongSidePx);
    } else {
      std::snprintf(text, sizeof(text), "1/%d: long side %d px over %d px", k, long_side, kWorkingLongSidePx);
    }
  }
  r.rule = text;
  r.width = static_cast<int>(std::lround(width * r.scale));
  r.height = static_cast<int>(std::lround(height * r.scale));
  return r;
}

std::string describe(const WorkingResolution& r) {
  char text[240];
  std::snprintf(text, sizeof(text), "working resolution %dx%d (scale %s)", r.width, r.height, r.rule.c_str());
  return text;
}

}  // namespace nadir::import
