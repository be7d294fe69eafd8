#pragma once
// The NovAtel SPAN logs the bridge understands, decoded but still in NovAtel's
// own conventions (degrees, north/east/up velocity, SPAN roll/pitch/azimuth).
// Conversion to project frames happens in novatel_attitude.h.

#include <cstdint>
#include <string>

namespace nadir::ins_bridge {

enum class NovatelFormat { kAscii, kShortAscii, kBinary, kShortBinary };
const char* format_name(NovatelFormat format);

// Message IDs (OEM6/OEM7 SPAN manuals).
inline constexpr uint16_t kInspvaId = 507;
inline constexpr uint16_t kInspvasId = 508;
inline constexpr uint16_t kInsstdevId = 2051;
// Binary body sizes in bytes.
inline constexpr uint16_t kInspvaBodySize = 88;
inline constexpr uint16_t kInsstdevBodySize = 52;
inline constexpr uint8_t kBinaryHeaderSize = 28;
inline constexpr uint8_t kShortBinaryHeaderSize = 12;

// INS solution status enum (InertialSolutionStatus).
enum InsStatus : int32_t {
  kInsInactive = 0,
  kInsAligning = 1,
  kInsHighVariance = 2,
  kInsSolutionGood = 3,
  kInsSolutionFree = 6,
  kInsAlignmentComplete = 7,
  kInsDeterminingOrientation = 8,
  kInsWaitingInitialPos = 9,
  kInsWaitingAzimuth = 10,
  kInsInitializingBiases = 11,
  kInsMotionDetect = 12,
  kInsWaitingAlignmentOrientation = 14,
};
// ASCII name <-> value; false / nullptr for names and values not in the enum.
bool ins_status_from_name(const std::string& name, int32_t* value);
const char* ins_status_name(int32_t value);

// INSPVA / INSPVAS body: solution time, WGS84 position, local-level velocity,
// SPAN attitude (roll about the IMU y axis, pitch about x, azimuth clockwise
// from north about -z; see novatel_attitude.h).
struct InsPva {
  uint32_t gps_week = 0;
  double gps_seconds = 0.0;
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double height_m = 0.0;      // ellipsoidal
  double north_velocity = 0.0;
  double east_velocity = 0.0;
  double up_velocity = 0.0;
  double roll_deg = 0.0;
  double pitch_deg = 0.0;
  double azimuth_deg = 0.0;
  int32_t status = kInsInactive;
};

// INSSTDEV body; its time is the log header's time.
struct InsStdDev {
  uint32_t gps_week = 0;
  double gps_seconds = 0.0;
  float latitude_m = 0, longitude_m = 0, height_m = 0;
  float north_velocity = 0, east_velocity = 0, up_velocity = 0;
  float roll_deg = 0, pitch_deg = 0, azimuth_deg = 0;
  uint32_t extended_status = 0;
  uint16_t time_since_update = 0;
};

// Field limits the parser enforces (a value outside is a decoding error).
struct InsLimits {
  static constexpr double kMaxWeek = 65535;          // ushort in every header
  static constexpr double kSecondsPerWeek = 604800;  // seconds in [0, 604800)
  static constexpr double kMaxHeight = 100000;       // m, |height|
  static constexpr double kMaxSpeed = 2000;          // m/s per component
  static constexpr double kMaxStdDev = 1e6;          // any sigma
};
// Empty when every field is finite and within limits, else the first offender.
std::string check_limits(const InsPva& pva);
std::string check_limits(const InsStdDev& stddev);

}  // namespace nadir::ins_bridge
