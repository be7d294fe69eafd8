#include "common/capture_accounting.h"

#include <algorithm>
#include <sstream>

#include "common/channels.h"
#include "common/message_guard.h"
#include "nadir/status_t.hpp"

namespace nadir {
namespace {

constexpr const char* kTxPrefix = "tx.";

}  // namespace

int64_t CaptureAccounting::missing_total() const {
  int64_t total = 0;
  for (const ChannelAccount& c : channels) total += c.missing();
  return total;
}

int64_t CaptureAccounting::udp_rx_drops_total() const {
  int64_t total = 0;
  for (const auto& [name, drops] : udp_rx_drops) total += drops;
  return total;
}

void CaptureAccountant::add(const LogEvent& event) {
  ++records_;
  if (event.channel != channels::kStatus) {
    ++captured_[event.channel];
    return;
  }
  status_t status;
  std::string reason;
  if (!decode_message(event.data, event.size, &status, &reason)) return;
  const ProcessRun run{status.name, status.pid};
  for (size_t i = 0; i < status.counter_names.size() && i < status.counter_values.size(); ++i) {
    const std::string& name = status.counter_names[i];
    const double value = status.counter_values[i];
    if (name == "udp_rx_drops") {
      udp_rx_drops_[run] = static_cast<int64_t>(value);
    } else if (name.rfind(kTxPrefix, 0) == 0) {
      const std::string channel = name.substr(3);
      snapshots_[channel][run] = Snapshot{static_cast<int64_t>(value), captured_[channel], records_};
    }
  }
}

CaptureAccounting CaptureAccountant::result() const {
  CaptureAccounting out;
  for (const auto& [channel, runs] : snapshots_) {
    ChannelAccount account;
    account.channel = channel;
    int64_t latest_order = -1;
    std::vector<std::string> names;
    for (const auto& [run, snapshot] : runs) {
      // Runs of one publisher (restarts) add up; the capture is judged up to
      // the latest of their STATUS records.
      account.published += snapshot.published;
      if (snapshot.order > latest_order) {
        latest_order = snapshot.order;
        account.captured = snapshot.captured_then;
      }
      if (std::find(names.begin(), names.end(), run.first) == names.end()) names.push_back(run.first);
    }
    for (const std::string& n : names) account.publishers += (account.publishers.empty() ? "" : ",") + n;
    out.channels.push_back(account);
  }
  for (const auto& [run, drops] : udp_rx_drops_) out.udp_rx_drops[run.first] += drops;
  return out;
}

std::string format_capture_accounting(const CaptureAccounting& accounting) {
  std::ostringstream out;
  for (const ChannelAccount& c : accounting.channels) {
    if (c.missing() > 0) {
      out << c.channel << ": " << c.missing() << " of " << c.published << " published by " << c.publishers
          << " missing from the capture\n";
    }
    if (c.unaccounted() > 0) {
      out << c.channel << ": " << c.unaccounted() << " record(s) more than " << c.publishers
          << " published (a second publisher without STATUS?)\n";
    }
  }
  for (const auto& [name, drops] : accounting.udp_rx_drops) {
    if (drops > 0) {
      out << name << ": " << drops << " datagram(s) dropped by the kernel (receive buffer full: the process was "
          << "stopped or too slow)\n";
    }
  }
  return out.str();
}

}  // namespace nadir
