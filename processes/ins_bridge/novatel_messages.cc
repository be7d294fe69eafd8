#include "processes/ins_bridge/novatel_messages.h"

#include <cmath>
#include <cstring>

namespace nadir::ins_bridge {
namespace {

struct StatusName {
  int32_t value;
  const char* name;
};
constexpr StatusName kStatusNames[] = {
    {kInsInactive, "INS_INACTIVE"},
    {kInsAligning, "INS_ALIGNING"},
    {kInsHighVariance, "INS_HIGH_VARIANCE"},
    {kInsSolutionGood, "INS_SOLUTION_GOOD"},
    {kInsSolutionFree, "INS_SOLUTION_FREE"},
    {kInsAlignmentComplete, "INS_ALIGNMENT_COMPLETE"},
    {kInsDeterminingOrientation, "DETERMINING_ORIENTATION"},
    {kInsWaitingInitialPos, "WAITING_INITIALPOS"},
    {kInsWaitingAzimuth, "WAITING_AZIMUTH"},
    {kInsInitializingBiases, "INITIALIZING_BIASES"},
    {kInsMotionDetect, "MOTION_DETECT"},
    {kInsWaitingAlignmentOrientation, "WAITING_ALIGNMENTORIENTATION"},
};

std::string in_range(const char* name, double value, double lo, double hi) {
  if (!std::isfinite(value)) return std::string(name) + " is not finite";
  if (value < lo || value > hi) {
    return std::string(name) + " = " + std::to_string(value) + " outside [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "]";
  }
  return {};
}

}  // namespace

const char* format_name(NovatelFormat format) {
  switch (format) {
    case NovatelFormat::kAscii: return "ascii";
    case NovatelFormat::kShortAscii: return "short_ascii";
    case NovatelFormat::kBinary: return "binary";
    case NovatelFormat::kShortBinary: return "short_binary";
  }
  return "?";
}

bool ins_status_from_name(const std::string& name, int32_t* value) {
  for (const StatusName& entry : kStatusNames) {
    if (name == entry.name) {
      *value = entry.value;
      return true;
    }
  }
  return false;
}

const char* ins_status_name(int32_t value) {
  for (const StatusName& entry : kStatusNames) {
    if (value == entry.value) return entry.name;
  }
  return nullptr;
}

std::string check_limits(const InsPva& pva) {
  std::string why;
  if (pva.gps_week > InsLimits::kMaxWeek) return "week = " + std::to_string(pva.gps_week) + " > 65535";
  if (!std::isfinite(pva.gps_seconds) || pva.gps_seconds < 0 || pva.gps_seconds >= InsLimits::kSecondsPerWeek) {
    return "seconds of week outside [0, 604800)";
  }
  if (!(why = in_range("latitude", pva.latitude_deg, -90, 90)).empty()) return why;
  if (!(why = in_range("longitude", pva.longitude_deg, -180, 180)).empty()) return why;
  if (!(why = in_range("height", pva.height_m, -InsLimits::kMaxHeight, InsLimits::kMaxHeight)).empty()) return why;
  if (!(why = in_range("north velocity", pva.north_velocity, -InsLimits::kMaxSpeed, InsLimits::kMaxSpeed)).empty())
    return why;
  if (!(why = in_range("east velocity", pva.east_velocity, -InsLimits::kMaxSpeed, InsLimits::kMaxSpeed)).empty())
    return why;
  if (!(why = in_range("up velocity", pva.up_velocity, -InsLimits::kMaxSpeed, InsLimits::kMaxSpeed)).empty())
    return why;
  if (!(why = in_range("roll", pva.roll_deg, -180, 180)).empty()) return why;
  if (!(why = in_range("pitch", pva.pitch_deg, -90, 90)).empty()) return why;
  if (!(why = in_range("azimuth", pva.azimuth_deg, 0, 360)).empty()) return why;
  if (ins_status_name(pva.status) == nullptr) return "INS status " + std::to_string(pva.status) + " is not in the enum";
  return {};
}

std::string check_limits(const InsStdDev& s) {
  if (s.gps_week > InsLimits::kMaxWeek) return "week > 65535";
  if (!std::isfinite(s.gps_seconds) || s.gps_seconds < 0 || s.gps_seconds >= InsLimits::kSecondsPerWeek) {
    return "seconds of week outside [0, 604800)";
  }
  const float values[] = {s.latitude_m,    s.longitude_m, s.height_m,  s.north_velocity, s.east_velocity,
                          s.up_velocity,   s.roll_deg,    s.pitch_deg, s.azimuth_deg};
  for (float v : values) {
    std::string why = in_range("standard deviation", v, 0, InsLimits::kMaxStdDev);
    if (!why.empty()) return why;
  }
  return {};
}

}  // namespace nadir::ins_bridge
