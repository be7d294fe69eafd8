#include "common/gps_time.h"

#include <cmath>
#include <cstdlib>

namespace nadir {
namespace {

// Days from 1970-01-01 to a civil date (proleptic Gregorian).
int64_t days_from_civil(int64_t y, unsigned m, unsigned d) {
  y -= m <= 2;
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<int64_t>(doe) - 719468;
}

struct LeapEntry {
  int year;
  unsigned month;
  int gps_minus_utc;  // from 00:00 UTC of that day
};
// Every change of GPS - UTC since the GPS epoch.
constexpr LeapEntry kLeapTable[] = {
    {1981, 7, 1},  {1982, 7, 2},  {1983, 7, 3},  {1985, 7, 4},  {1988, 1, 5},  {1990, 1, 6},
    {1991, 1, 7},  {1992, 7, 8},  {1993, 7, 9},  {1994, 7, 10}, {1996, 1, 11}, {1997, 7, 12},
    {1999, 1, 13}, {2006, 1, 14}, {2009, 1, 15}, {2012, 7, 16}, {2015, 7, 17}, {2017, 1, 18},
};

int64_t change_gps_us(const LeapEntry& e) {
  const int64_t unix_s = days_from_civil(e.year, e.month, 1) * 86400;
  return (unix_s - kGpsEpochUnixSeconds + e.gps_minus_utc) * 1000000;
}

}  // namespace

int64_t gps_time_us(uint32_t week, double seconds_of_week) {
  return static_cast<int64_t>(week) * kSecondsPerWeek * 1000000 + std::llround(seconds_of_week * 1e6);
}

int leap_seconds_at(int64_t gps_us) {
  int leap = 0;
  for (const LeapEntry& e : kLeapTable) {
    if (gps_us >= change_gps_us(e)) leap = e.gps_minus_utc;
  }
  return leap;
}

int64_t gps_to_unix_us(int64_t gps_us, int leap_seconds) {
  return gps_us + (kGpsEpochUnixSeconds - leap_seconds) * 1000000;
}

int64_t unix_to_gps_us(int64_t unix_us) {
  const int64_t first_guess = unix_us - kGpsEpochUnixSeconds * 1000000;
  return first_guess + static_cast<int64_t>(leap_seconds_at(first_guess)) * 1000000;
}

uint32_t unwrap_week_1024(uint32_t week, double seconds_of_week, int64_t reference_gps_us) {
  const uint32_t base = week % 1024;
  uint32_t best = base;
  int64_t best_error = INT64_MAX;
  for (uint32_t k = 0; k < 64; ++k) {
    const uint32_t candidate = base + 1024 * k;
    const int64_t error = std::llabs(gps_time_us(candidate, seconds_of_week) - reference_gps_us);
    if (error < best_error) {
      best_error = error;
      best = candidate;
    }
  }
  return best;
}

}  // namespace nadir
