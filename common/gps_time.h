#pragma once
// GPS time (weeks + seconds since 1980-01-06, no leap seconds) to UTC-based
// Unix time, with the leap-second table and the 1024-week ambiguity explicit.

#include <cstdint>

namespace nadir {

inline constexpr int64_t kGpsEpochUnixSeconds = 315964800;  // 1980-01-06T00:00:00Z
inline constexpr int64_t kSecondsPerWeek = 604800;

// Microseconds since the GPS epoch.
int64_t gps_time_us(uint32_t week, double seconds_of_week);
// GPS - UTC in whole seconds at a GPS time, from the IERS table built in here
// (last entry 2017-01-01: 18 s). A future leap second needs a table entry or
// the `leap_seconds` option.
int leap_seconds_at(int64_t gps_us);
// UTC Unix microseconds of a GPS time with GPS - UTC = leap_seconds.
int64_t gps_to_unix_us(int64_t gps_us, int leap_seconds);
// GPS microseconds of a UTC Unix time (inverse, table leap seconds).
int64_t unix_to_gps_us(int64_t unix_us);
// A week number that may have been reported modulo 1024 (old receivers,
// GPS week-number rollovers of 1999 and 2019), resolved to the full week
// whose time is nearest `reference_gps_us`.
uint32_t unwrap_week_1024(uint32_t week, double seconds_of_week, int64_t reference_gps_us);

}  // namespace nadir
