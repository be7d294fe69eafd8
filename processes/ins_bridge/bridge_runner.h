#pragma once
// The live loop of nadir_ins_bridge: poll() over both serial devices and the
// LCM fd, feed arriving bytes (stamped on the vehicle time base) to InsBridge,
// close and reopen a device that hangs up, fails or stalls, publish STATUS
// periodically. Reopen policy: while the path is absent (unplugged) it is
// polled every absent_poll_s; exponential backoff (reopen_min_s doubling up to
// reopen_max_s) only for a device that is there but fails to open or hangs up
// again before sending a byte. One device's trouble never blocks
// the other: every fd is non-blocking and served from the same poll.

#include <cstdint>
#include <functional>
#include <string>

#include "common/lcm_bus.h"
#include "common/status.h"
#include "processes/ins_bridge/ins_bridge.h"
#include "common/serial_port.h"

namespace nadir::ins_bridge {

struct DeviceLinkCounters {
  int64_t opens = 0;
  int64_t open_failures = 0;   // the device is there but would not open: backoff
  int64_t absent_polls = 0;    // opens tried while nothing was at the path
  int64_t hangups = 0;
  int64_t stalls = 0;
  std::string last_error;
};

class BridgeRunner {
 public:
  BridgeRunner(const BridgeOptions& options, LcmBus& bus, std::string name = "ins_bridge",
               double status_period_s = 1.0);

  // One round: waits at most max_wait_ms for bytes or LCM traffic.
  void step(int max_wait_ms);
  // Steps until keep_running() is false; then publishes a STOPPING status.
  void run(const std::function<bool()>& keep_running);

  StatusReport status() const;
  void publish_status(int8_t forced_state = -1);
  const InsBridge& bridge() const { return bridge_; }
  const DeviceLinkCounters& ins_link() const { return ins_.counters; }
  const DeviceLinkCounters& altimeter_link() const { return alt_.counters; }
  bool ins_open() const { return ins_.port.is_open(); }
  bool altimeter_open() const { return alt_.port.is_open(); }

 private:
  struct Link {
    explicit Link(const SerialOptions& options) : port(options) {}
    SerialPort port;
    DeviceLinkCounters counters;
    int64_t next_open_us = 0;     // monotonic
    double backoff_s = 0.0;
    int64_t last_byte_us = 0;     // monotonic
    bool ever_opened = false;
  };
  void service_opens(int64_t now_us);
  void try_open(Link& link, bool is_ins, int64_t now_us);
  void back_off(Link& link, int64_t now_us);
  void drop(Link& link, bool is_ins, int64_t now_us, const std::string& why, int64_t* counter);
  void read_link(Link& link, bool is_ins);
  int64_t next_deadline_us() const;

  BridgeOptions options_;
  LcmBus& bus_;
  std::string name_;
  int64_t status_period_us_;
  int64_t next_status_us_ = 0;
  InsBridge bridge_;
  Link ins_;
  Link alt_;
};

}  // namespace nadir::ins_bridge
