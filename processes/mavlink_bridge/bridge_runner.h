#pragma once
// The live loop of nadir_mavlink_bridge: poll() over the link (a UDP socket
// or a serial device) and the LCM fd; bytes to MavlinkBridge stamped on the
// vehicle time base, frames from it to the link; HEARTBEAT/TIMESYNC ticks and
// STATUS periodically. A serial device that hangs up or stalls is closed and
// reopened after reopen_min_s (as the INS bridge's links, without backoff).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "common/lcm_bus.h"
#include "common/status.h"
#include "common/serial_port.h"
#include "processes/mavlink_bridge/mavlink_bridge.h"
#include "processes/mavlink_bridge/udp_link.h"

namespace nadir::mavlink_bridge {

class BridgeRunner {
 public:
  // Throws std::runtime_error when a UDP socket cannot be bound.
  BridgeRunner(const BridgeOptions& options, LcmBus& bus, std::string name = "mavlink_bridge",
               double status_period_s = 1.0);

  void step(int max_wait_ms);
  void run(const std::function<bool()>& keep_running);

  StatusReport status() const;
  void publish_status(int8_t forced_state = -1);
  const MavlinkBridge& bridge() const { return bridge_; }
  uint16_t udp_port() const { return udp_ ? udp_->local_port() : 0; }
  int64_t udp_peer_changes() const { return udp_ ? udp_->peer_changes() : 0; }
  int64_t udp_foreign_datagrams() const { return udp_ ? udp_->foreign_datagrams() : 0; }

 private:
  void write(const std::vector<uint8_t>& frame);
  void service_serial(int64_t now_us);
  void read_udp();
  void read_serial();

  BridgeOptions options_;
  LcmBus& bus_;
  std::string name_;
  int64_t status_period_us_;
  int64_t next_status_us_ = 0;
  std::unique_ptr<UdpLink> udp_;
  std::unique_ptr<SerialPort> serial_;
  MavlinkBridge bridge_;
  int64_t serial_next_open_us_ = 0;
  int64_t serial_last_byte_us_ = 0;
  bool serial_ever_opened_ = false;
  int64_t serial_reopens_ = 0;
  int64_t write_failures_ = 0;
  std::string link_error_;
};

}  // namespace nadir::mavlink_bridge
