#pragma once
// Writes the messages of one channel of a log as CSV (a header, then one row
// per message, or per track for TRACKS) or as JSON lines (one object per row).
// The message type is recognised by its fingerprint, so any channel carrying a
// supported type can be dumped. Corrupt log records are skipped by LogReader;
// messages that do not decode are skipped by the message guard; both counted.

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace nadir {

enum class DumpFormat { kCsv, kJsonLines };

struct DumpStats {
  int64_t messages = 0;         // messages on the channel that decoded
  int64_t rows = 0;             // rows written
  int64_t corrupt_records = 0;  // log records skipped by the reader (whole file)
  bool truncated = false;
  int64_t undecodable = 0;      // messages on the channel the guard rejected
  std::string type;             // "nadir.tracks_t", ...
  std::string damage_report;    // the reader's "FILE: byte N: what" lines
  std::string first_decode_error;
};

// The nadir types dump understands, e.g. "nadir.vo_delta_t".
std::vector<std::string> dumpable_types();

// Throws std::runtime_error naming the file and the channel when the file
// cannot be read, the channel has no decodable message, or its type is not
// supported.
DumpStats dump_channel(const std::string& path, const std::string& channel, DumpFormat format, std::ostream& out);

}  // namespace nadir
