#pragma once
// The vehicle time base: microseconds of the host's CLOCK_REALTIME. Bridges map
// device time (GPS time, CLOCK_MONOTONIC GPIO edges, camera clocks) onto it;
// estimators only ever see sensor time on this base, never receive time.

#include <cstdint>

namespace nadir {

int64_t vehicle_time_now_us();
int64_t monotonic_now_us();
// Maps a CLOCK_MONOTONIC time to the vehicle time base (same instant).
int64_t monotonic_to_vehicle_us(int64_t monotonic_us);

inline double us_to_s(int64_t us) { return static_cast<double>(us) * 1e-6; }
inline int64_t s_to_us(double s) { return static_cast<int64_t>(s * 1e6 + (s >= 0 ? 0.5 : -0.5)); }

}  // namespace nadir
