#pragma once
// Per-frame telemetry of a recorded video: a DJI-style .SRT subtitle file or a
// generic CSV with named columns. Parse errors name the file and the line; with
// `skip_bad` a bad block / line is skipped and counted instead.

#include <string>
#include <vector>

namespace nadir::import {

// One telemetry record. Angles in degrees as the source gives them.
struct TelemetryRecord {
  int line = 0;                 // first line of the record in its file (1-based)
  double time_s = 0.0;          // SRT: start of the subtitle; CSV: time_s column
  double absolute_time_s = -1;  // SRT date-time line as UNIX seconds (UTC as written), -1 if absent
  int64_t frame = -1;           // SRT FrameCnt (1-based), -1 if absent
  bool has_gimbal = false;      // SRT gb_yaw/gb_pitch/gb_roll: the camera attitude (DJI gimbal convention)
  double gimbal_roll_deg = 0, gimbal_pitch_deg = 0, gimbal_yaw_deg = 0;
  bool has_body = false;        // SRT flight_*, CSV roll/pitch/yaw: the body attitude (nadir's ZYX convention)
  double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;
  bool has_range = false;       // laser range (m): used as a rangefinder
  double range_m = 0;
  bool has_height = false;      // height above take-off (m): barometric relative
  double height_m = 0;
  double lat_deg = 0, lon_deg = 0;
  bool has_alt = false;
  double alt_m = 0;
};

struct SkippedInput {
  std::string where;   // "FILE:LINE" or "FILE"
  std::string reason;
};

struct Telemetry {
  std::string path;
  std::vector<TelemetryRecord> records;
  std::vector<SkippedInput> skipped;
};

// Throws std::runtime_error "FILE:LINE: what" on the first bad block / line
// unless skip_bad, which records it in `skipped` and goes on.
Telemetry parse_srt_text(const std::string& text, const std::string& path, bool skip_bad);
Telemetry parse_csv_text(const std::string& text, const std::string& path, bool skip_bad);
Telemetry read_srt(const std::string& path, bool skip_bad);
Telemetry read_csv(const std::string& path, bool skip_bad);

// Text helpers shared with photo_metadata.cc: blanks (space, tab, CR, LF) trimmed;
// a whole-string finite number (false otherwise).
std::string trim(const std::string& text);
bool parse_number(const std::string& text, double* value);

// "YYYY-MM-DD HH:MM:SS[.fff]" or "YYYY:MM:DD HH:MM:SS" (EXIF) or "YYYY-MM-DDTHH:MM:SS" as UNIX
// seconds, the clock's time zone taken as UTC; false when it does not parse.
bool parse_date_time(const std::string& text, double* unix_s);

}  // namespace nadir::import
