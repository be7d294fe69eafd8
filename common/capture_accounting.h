#pragma once
// Checks a capture against what its publishers say they sent. Every live
// process's STATUS counts the messages it published per channel
// ("tx.<CHANNEL>", LcmBus::add_transport_counters); a capture that holds fewer
// of a channel's records before that STATUS than the count lost them on the
// way (the logger stopped or its receive buffer overflowed). A capture that
// holds more has a publisher that sends no STATUS: a second publisher on the
// channel. Receivers' own kernel drops ("udp_rx_drops") are collected too: a
// process that was stopped or starved lost input there, not in the capture.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/log_file.h"

namespace nadir {

struct ChannelAccount {
  std::string channel;
  std::string publishers;   // process names whose STATUS counts the channel
  int64_t published = 0;    // their tx counts at their last STATUS in the capture
  int64_t captured = 0;     // the channel's records in the capture before that STATUS
  int64_t missing() const { return published > captured ? published - captured : 0; }
  int64_t unaccounted() const { return captured > published ? captured - published : 0; }
};

struct CaptureAccounting {
  std::vector<ChannelAccount> channels;          // channels some STATUS counts
  std::map<std::string, int64_t> udp_rx_drops;   // per process name, summed over its runs (pids)
  int64_t missing_total() const;
  int64_t udp_rx_drops_total() const;
};

class CaptureAccountant {
 public:
  void add(const LogEvent& event);
  CaptureAccounting result() const;

 private:
  struct Snapshot {
    int64_t published = 0;
    int64_t captured_then = 0;
    int64_t order = 0;  // record index of the STATUS
  };
  using ProcessRun = std::pair<std::string, int32_t>;  // name, pid
  int64_t records_ = 0;
  std::map<std::string, int64_t> captured_;                          // per channel, so far
  std::map<std::string, std::map<ProcessRun, Snapshot>> snapshots_;  // per channel, per run: last STATUS
  std::map<ProcessRun, int64_t> udp_rx_drops_;                       // per run: last STATUS
};

// Lines for a report: "INS: 3 of 3000 published missing from the capture
// (publisher sim)"; empty when nothing is missing, unaccounted or dropped.
std::string format_capture_accounting(const CaptureAccounting& accounting);

}  // namespace nadir
