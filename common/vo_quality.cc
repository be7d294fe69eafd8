#include "common/vo_quality.h"

#include "nadir/vo_delta_t.hpp"

namespace nadir {

namespace {
const char* const kNames[kVoQualityBits] = {"too_few_features", "no_altimeter",  "stale_altimeter",
                                            "not_converged",    "no_attitude",   "frame_gap",
                                            "high_residual",    "depth_layers",  "heading_contradicts"};
static_assert(vo_delta_t::QUALITY_HEADING_CONTRADICTS == 1 << (kVoQualityBits - 1),
              "a new QUALITY_* bit needs its name here");
}  // namespace

const char* vo_quality_name(int bit) { return bit >= 0 && bit < kVoQualityBits ? kNames[bit] : ""; }

std::string vo_quality_names(int32_t quality) {
  std::string out;
  for (int bit = 0; bit < kVoQualityBits; ++bit) {
    if (quality & (1 << bit)) out += std::string(out.empty() ? "" : ", ") + kNames[bit];
  }
  return out;
}

}  // namespace nadir
