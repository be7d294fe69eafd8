#pragma once
// The state of every process seen on STATUS, for nadir_status.

#include <cstdint>
#include <map>
#include <string>

#include "nadir/status_t.hpp"

namespace nadir {

struct ProcessRow {
  status_t last{};
  int64_t heard_us = 0;      // monotonic time the last STATUS arrived
  double rx_rate_hz = 0.0;   // from the received counter between heartbeats
  double tx_rate_hz = 0.0;
};

class StatusTable {
 public:
  explicit StatusTable(double stale_after_s) : stale_after_s_(stale_after_s) {}
  void update(const status_t& status, int64_t now_us);
  bool stale(const ProcessRow& row, int64_t now_us) const;
  const std::map<std::string, ProcessRow>& rows() const { return rows_; }
  std::string format(int64_t now_us) const;
  std::string json(int64_t now_us) const;

 private:
  double stale_after_s_;
  std::map<std::string, ProcessRow> rows_;
};

}  // namespace nadir
