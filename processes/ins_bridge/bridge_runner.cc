#include "processes/ins_bridge/bridge_runner.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "common/channels.h"
#include "common/time_base.h"

namespace nadir::ins_bridge {

BridgeRunner::BridgeRunner(const BridgeOptions& options, LcmBus& bus, std::string name, double status_period_s)
    : options_(options),
      bus_(bus),
      name_(std::move(name)),
      status_period_us_(s_to_us(status_period_s)),
      bridge_(options, bus),
      ins_(options.ins.serial),
      alt_(options.altimeter.serial) {
  next_status_us_ = monotonic_now_us() + status_period_us_;
}

void BridgeRunner::try_open(Link& link, bool is_ins, int64_t now_us) {
  std::string error;
  const SerialPort::OpenResult result = link.port.open(&error);
  if (result == SerialPort::OpenResult::kOpened) {
    ++link.counters.opens;
    link.last_byte_us = now_us;  // the stall clock starts at the open
    if (link.ever_opened) {
      if (is_ins) bridge_.on_ins_reopened();
      else bridge_.on_altimeter_reopened();
    }
    link.ever_opened = true;
    std::fprintf(stderr, "nadir_ins_bridge: opened %s (%s, %d baud)\n", link.port.options().device.c_str(),
                 is_ins ? "INS" : "altimeter", link.port.options().baud);
    return;
  }
  if (error != link.counters.last_error) std::fprintf(stderr, "nadir_ins_bridge: %s\n", error.c_str());
  link.counters.last_error = error;
  if (result == SerialPort::OpenResult::kAbsent) {
    // Unplugged: poll the path at a fixed short interval so a device that comes
    // back is read at once (a USB adapter drops what it sends while closed).
    ++link.counters.absent_polls;
    link.backoff_s = 0;
    link.next_open_us = now_us + s_to_us(link.port.options().absent_poll_s);
    return;
  }
  ++link.counters.open_failures;  // there but refusing: back off
  back_off(link, now_us);
}

void BridgeRunner::back_off(Link& link, int64_t now_us) {
  const SerialOptions& o = link.port.options();
  link.backoff_s = link.backoff_s <= 0 ? o.reopen_min_s : std::min(o.reopen_max_s, link.backoff_s * 2);
  link.next_open_us = now_us + s_to_us(link.backoff_s);
}

void BridgeRunner::drop(Link& link, bool is_ins, int64_t now_us, const std::string& why, int64_t* counter) {
  ++*counter;
  link.counters.last_error = why;
  std::fprintf(stderr, "nadir_ins_bridge: %s: %s; reopening\n", is_ins ? "INS" : "altimeter", why.c_str());
  link.port.close();
  // A device that hangs up again before sending anything backs off too.
  back_off(link, now_us);
}

void BridgeRunner::service_opens(int64_t now_us) {
  for (Link* link : {&ins_, &alt_}) {
    const bool is_ins = link == &ins_;
    if (!link->port.is_open()) {
      if (now_us >= link->next_open_us) try_open(*link, is_ins, now_us);
    } else if (now_us - link->last_byte_us > s_to_us(link->port.options().stall_timeout_s)) {
      drop(*link, is_ins, now_us,
           link->port.options().device + ": no byte for " + std::to_string(link->port.options().stall_timeout_s) + " s",
           &link->counters.stalls);
    }
  }
}

void BridgeRunner::read_link(Link& link, bool is_ins) {
  uint8_t buffer[4096];
  // Bounded per round so a flood on one device cannot starve the other.
  for (int round = 0; round < 8 && link.port.is_open(); ++round) {
    size_t got = 0;
    std::string error;
    const SerialPort::ReadResult result = link.port.read_some(buffer, sizeof buffer, &got, &error);
    const int64_t now = monotonic_now_us();
    if (result == SerialPort::ReadResult::kHangup) {
      drop(link, is_ins, now, error, &link.counters.hangups);
      return;
    }
    if (result == SerialPort::ReadResult::kNothing) return;
    link.last_byte_us = now;
    link.backoff_s = 0;  // data flows: the next failure starts the backoff afresh
    const int64_t arrival = monotonic_to_vehicle_us(now);
    if (is_ins) bridge_.on_ins_bytes(buffer, got, arrival);
    else bridge_.on_altimeter_bytes(buffer, got, arrival);
    if (got < sizeof buffer) return;
  }
}

int64_t BridgeRunner::next_deadline_us() const {
  int64_t deadline = next_status_us_;
  for (const Link* link : {&ins_, &alt_}) {
    if (!link->port.is_open()) deadline = std::min(deadline, link->next_open_us);
    else deadline = std::min(deadline, link->last_byte_us + s_to_us(link->port.options().stall_timeout_s) + 1000);
  }
  return deadline;
}

void BridgeRunner::step(int max_wait_ms) {
  service_opens(monotonic_now_us());
  pollfd fds[3];
  int n = 0;
  const int lcm_index = n;
  fds[n++] = pollfd{bus_.fileno(), POLLIN, 0};
  const int ins_index = ins_.port.is_open() ? n : -1;
  if (ins_index >= 0) fds[n++] = pollfd{ins_.port.fd(), POLLIN, 0};
  const int alt_index = alt_.port.is_open() ? n : -1;
  if (alt_index >= 0) fds[n++] = pollfd{alt_.port.fd(), POLLIN, 0};

  const int64_t wait_us = std::max<int64_t>(0, next_deadline_us() - monotonic_now_us());
  const int timeout_ms = static_cast<int>(std::min<int64_t>(max_wait_ms, (wait_us + 999) / 1000));
  const int ready = ::poll(fds, static_cast<nfds_t>(n), timeout_ms);
  if (ready > 0) {
    auto serve = [&](int index, Link& link, bool is_ins) {
      if (index < 0 || fds[index].revents == 0) return;
      if (fds[index].revents & POLLIN) read_link(link, is_ins);
      // POLLHUP with data still queued: read it first (above), then drop.
      if (link.port.is_open() && (fds[index].revents & (POLLHUP | POLLERR | POLLNVAL)) &&
          !(fds[index].revents & POLLIN)) {
        drop(link, is_ins, monotonic_now_us(), link.port.options().device + ": hangup", &link.counters.hangups);
      }
    };
    serve(ins_index, ins_, true);
    serve(alt_index, alt_, false);
    if (fds[lcm_index].revents & POLLIN) bus_.handle(0);
  }
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
  auto link_counters = [&](const char* prefix, const Link& link) {
    const std::string p = prefix;
    r.counters.emplace_back(p + "_open", link.port.is_open() ? 1.0 : 0.0);
    r.counters.emplace_back(p + "_opens", static_cast<double>(link.counters.opens));
    r.counters.emplace_back(p + "_open_failures", static_cast<double>(link.counters.open_failures));
    r.counters.emplace_back(p + "_absent_polls", static_cast<double>(link.counters.absent_polls));
    r.counters.emplace_back(p + "_hangups", static_cast<double>(link.counters.hangups));
    r.counters.emplace_back(p + "_stalls", static_cast<double>(link.counters.stalls));
    // Device faults; rejected input is STATUS `malformed` (publish_status).
    r.errors += link.counters.hangups + link.counters.stalls + link.counters.open_failures;
    if (!link.port.is_open()) {
      if (r.state == status_t::STATE_OK) r.state = status_t::STATE_WARN;
      if (!r.detail.empty()) r.detail += "; ";
      r.detail +=
          link.counters.last_error.empty() ? link.port.options().device + ": not open" : link.counters.last_error;
    }
  };
  link_counters("ins_link", ins_);
  link_counters("alt_link", alt_);
  return r;
}

void BridgeRunner::publish_status(int8_t forced_state) {
  StatusReport report = status();
  if (forced_state >= 0) report.state = forced_state;
  status_t msg = bus_.status_message(name_, report);
  // Serial input that failed to decode is malformed input as much as a bad
  // LCM message: rejected INS sentences and altimeter lines.
  msg.malformed += bridge_.rejected_sentences();
  bus_.publish(channels::kStatus, msg);
}

}  // namespace nadir::ins_bridge
