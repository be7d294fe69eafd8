#include "processes/mavlink_bridge/bridge_runner.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "common/channels.h"
#include "common/time_base.h"
#include "nadir/pose_t.hpp"

namespace nadir::mavlink_bridge {

BridgeRunner::BridgeRunner(const BridgeOptions& options, LcmBus& bus, std::string name, double status_period_s)
    : options_(options),
      bus_(bus),
      name_(std::move(name)),
      status_period_us_(s_to_us(status_period_s)),
      bridge_(options, bus, [this](const std::vector<uint8_t>& frame) { write(frame); }) {
  if (options.link.kind == "serial") {
    serial_ = std::make_unique<SerialPort>(options.link.serial);
  } else {
    udp_ = std::make_unique<UdpLink>(options.link.kind == "udp_server", options.link.local, options.link.remote,
                                     options.link.autopilot_address);
    udp_->open();
  }
  bus_.subscribe<pose_t>(channels::kPose, [this](const pose_t& pose) { bridge_.on_pose(pose); });
  next_status_us_ = monotonic_now_us() + status_period_us_;
}

void BridgeRunner::write(const std::vector<uint8_t>& frame) {
  if (udp_) {
    // A server has nobody to send to until the autopilot has sent something.
    if (udp_->has_peer() && !udp_->send(frame.data(), frame.size())) ++write_failures_;
    return;
  }
  if (!serial_->is_open()) return;
  // Non-blocking: a frame that does not fit in the device's buffer now is
  // dropped whole rather than blocking the loop (counted).
  const ssize_t n = ::write(serial_->fd(), frame.data(), frame.size());
  if (n != static_cast<ssize_t>(frame.size())) {
    ++write_failures_;
    link_error_ = serial_->options().device + ": write: " + (n < 0 ? std::strerror(errno) : "short write");
  }
}

void BridgeRunner::service_serial(int64_t now_us) {
  if (!serial_) return;
  const SerialOptions& o = serial_->options();
  if (serial_->is_open()) {
    if (now_us - serial_last_byte_us_ > s_to_us(o.stall_timeout_s)) {
      link_error_ = o.device + ": no byte for " + std::to_string(o.stall_timeout_s) + " s";
      std::fprintf(stderr, "nadir_mavlink_bridge: %s; reopening\n", link_error_.c_str());
      serial_->close();
      serial_next_open_us_ = now_us + s_to_us(o.reopen_min_s);
    }
    return;
  }
  if (now_us < serial_next_open_us_) return;
  std::string error;
  if (serial_->open(&error) == SerialPort::OpenResult::kOpened) {
    serial_last_byte_us_ = now_us;
    if (serial_ever_opened_) {
      ++serial_reopens_;
      bridge_.on_link_reopened();
    }
    serial_ever_opened_ = true;
    std::fprintf(stderr, "nadir_mavlink_bridge: opened %s (%d baud)\n", o.device.c_str(), o.baud);
    return;
  }
  if (error != link_error_) std::fprintf(stderr, "nadir_mavlink_bridge: %s\n", error.c_str());
  link_error_ = error;
  serial_next_open_us_ = now_us + s_to_us(o.absent_poll_s);
}

void BridgeRunner::read_udp() {
  std::vector<uint8_t> datagram;
  // Bounded per round so a flood cannot starve LCM.
  sockaddr_in from{};
  for (int i = 0; i < 64 && udp_->receive(&datagram, &from); ++i) {
    // Replies go where the autopilot's valid frames come from, never to the
    // sender of a datagram that decoded to nothing of the autopilot's.
    if (bridge_.on_bytes(datagram.data(), datagram.size(), vehicle_time_now_us(), 0.0, true) > 0) {
      udp_->set_peer(from);
    }
  }
}

void BridgeRunner::read_serial() {
  uint8_t buffer[4096];
  for (int round = 0; round < 8 && serial_->is_open(); ++round) {
    size_t got = 0;
    std::string error;
    const auto result = serial_->read_some(buffer, sizeof buffer, &got, &error);
    const int64_t now = monotonic_now_us();
    if (result == SerialPort::ReadResult::kHangup) {
      link_error_ = error;
      std::fprintf(stderr, "nadir_mavlink_bridge: %s; reopening\n", error.c_str());
      serial_->close();
      serial_next_open_us_ = now + s_to_us(serial_->options().reopen_min_s);
      return;
    }
    if (result == SerialPort::ReadResult::kNothing) return;
    serial_last_byte_us_ = now;
    bridge_.on_bytes(buffer, got, monotonic_to_vehicle_us(now), serial_->options().byte_time_us(), false);
    if (got < sizeof buffer) return;
  }
}

void BridgeRunner::step(int max_wait_ms) {
  service_serial(monotonic_now_us());
  pollfd fds[2];
  int n = 0;
  fds[n++] = pollfd{bus_.fileno(), POLLIN, 0};
  const int link_fd = udp_ ? udp_->fd() : (serial_->is_open() ? serial_->fd() : -1);
  if (link_fd >= 0) fds[n++] = pollfd{link_fd, POLLIN, 0};
  // Wake for the next heartbeat/timesync tick: at least 20 Hz.
  const int timeout_ms = std::min(max_wait_ms, 50);
  const int ready = ::poll(fds, static_cast<nfds_t>(n), timeout_ms);
  if (ready > 0) {
    if (n > 1 && (fds[1].revents & (POLLIN | POLLHUP | POLLERR))) {
      if (udp_) read_udp();
      else read_serial();
    }
    if (fds[0].revents & POLLIN) bus_.handle(0);
  }
  bridge_.tick(vehicle_time_now_us());
  const int64_t now = monotonic_now_us();
  if (now >= next_status_us_) {
    publish_status();
    next_status_us_ = now + status_period_us_;
  }
}

void BridgeRunner::run(const std::function<bool()>& keep_running) {
  while (keep_running()) step(100);
  publish_status(status_t::STATE_STOPPING);
}

StatusReport BridgeRunner::status() const {
  StatusReport r;
  bridge_.report(&r);
  r.counters.emplace_back("link_write_failures", static_cast<double>(write_failures_));
  r.errors += write_failures_;
  if (udp_) {
    r.counters.emplace_back("udp_datagrams_in", static_cast<double>(udp_->datagrams_in()));
    r.counters.emplace_back("udp_datagrams_out", static_cast<double>(udp_->datagrams_out()));
    r.counters.emplace_back("udp_peer_changes", static_cast<double>(udp_->peer_changes()));
    if (udp_->pinned()) r.counters.emplace_back("udp_foreign_datagrams", static_cast<double>(udp_->foreign_datagrams()));
    if (udp_->datagrams_in() == 0) {
      if (r.state == status_t::STATE_OK) r.state = status_t::STATE_WARN;
      r.detail += std::string(r.detail.empty() ? "" : "; ") + "UDP: nothing heard on " + options_.link.local;
    }
  } else {
    r.counters.emplace_back("serial_open", serial_->is_open() ? 1.0 : 0.0);
    r.counters.emplace_back("serial_reopens", static_cast<double>(serial_reopens_));
    if (!serial_->is_open()) {
      if (r.state == status_t::STATE_OK) r.state = status_t::STATE_WARN;
      r.detail += std::string(r.detail.empty() ? "" : "; ") +
                  (link_error_.empty() ? serial_->options().device + ": not open" : link_error_);
    }
  }
  return r;
}

void BridgeRunner::publish_status(int8_t forced_state) {
  StatusReport report = status();
  if (forced_state >= 0) report.state = forced_state;
  status_t msg = bus_.status_message(name_, report);
  // Link bytes that decoded to nothing are malformed input as much as a bad LCM message.
  msg.malformed += bridge_.rejected_frames();
  bus_.publish(channels::kStatus, msg);
}

}  // namespace nadir::mavlink_bridge
