#pragma once
// Writes an LCM log as an MCAP file with the topics and JSON schemas the
// Foxglove bridge serves (FoxgloveTranslator), so a recorded flight opens in
// Foxglove with the same layout as a live one. Each message's log time is
// the LCM log's event time, its publish time the message's sensor time.

#include <cstdint>
#include <map>
#include <string>

#include "common/geodetic.h"

namespace nadir {

struct McapExportOptions {
  bool origin_from_ins = true;  // POSE's NED origin: the INS position at the first POSE ...
  GeodeticPoint origin;         // ... or this one
  double image_rate_hz = 0.0;  // CAMERA_IMAGE at most this often; 0: every frame
  size_t chunk_size = 4u << 20;
};

struct McapExportStats {
  int64_t log_events = 0;
  int64_t messages = 0;                         // MCAP messages written
  std::map<std::string, int64_t> lcm_messages;  // per LCM channel exported
  std::map<std::string, int64_t> skipped;       // LCM channels without a topic
  int64_t undecodable = 0;
  int64_t images_decimated = 0;
  int64_t corrupt_records = 0;
  uint32_t chunks = 0;
};

// Throws std::runtime_error naming the file when the log cannot be read or
// the MCAP file cannot be written.
McapExportStats export_mcap(const std::string& log_path, const std::string& mcap_path,
                            const McapExportOptions& options);

}  // namespace nadir
