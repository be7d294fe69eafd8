#pragma once
// Names of VO_DELTA's quality bits (vo_delta_t::QUALITY_*), for STATUS
// counters, reports and logs: one list, so that every reader says the same.

#include <cstdint>
#include <string>

namespace nadir {

constexpr int kVoQualityBits = 9;

// "too_few_features", ... for bit 0 .. kVoQualityBits - 1; "" beyond.
const char* vo_quality_name(int bit);

// The set bits of `quality` by name, joined by ", " ("" for 0).
std::string vo_quality_names(int32_t quality);

}  // namespace nadir
