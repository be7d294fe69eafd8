#include "common/time_base.h"

#include <ctime>

namespace nadir {
namespace {
int64_t clock_us(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000 + ts.tv_nsec / 1000;
}
}  // namespace

int64_t vehicle_time_now_us() { return clock_us(CLOCK_REALTIME); }
int64_t monotonic_now_us() { return clock_us(CLOCK_MONOTONIC); }

int64_t monotonic_to_vehicle_us(int64_t monotonic_us) {
  // Sample both clocks back to back; the bracket keeps the mapping error to
  // the time of one clock_gettime call.
  const int64_t mono_before = monotonic_now_us();
  const int64_t real = vehicle_time_now_us();
  const int64_t mono_after = monotonic_now_us();
  const int64_t offset = real - (mono_before + mono_after) / 2;
  return monotonic_us + offset;
}

}  // namespace nadir
