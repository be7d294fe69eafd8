// nadir_sim_mavlink: plays the simulator's attitude and altimeter as an
// autopilot would over MAVLink UDP, and relays everything else it hears from
// the simulator (camera, trigger, ground truth, ...) onto the live bus; the
// simulator's STATUS with its transport counts marked as its own bus's, and
// not LCM's self test.

#include <poll.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <exception>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/message_guard.h"
#include "common/shutdown.h"
#include "common/status.h"
#include "common/time_base.h"
#include "processes/mavlink_bridge/udp_link.h"
#include "tools/sim_mavlink/sim_autopilot.h"

namespace {

using namespace nadir;

// Simulator bus -> autopilot (INS, ALTIMETER) or relayed unchanged.
class SimRelay {
 public:
  SimRelay(LcmBus& bus, sim_mavlink::SimAutopilot& autopilot) : bus_(bus), autopilot_(autopilot) {}
  void handle(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    const auto* data = static_cast<const uint8_t*>(rbuf->data);
    const size_t size = rbuf->data_size;
    std::string reason;
    if (channel == channels::kIns) {
      ins_t ins;
      if (decode_message(data, size, &ins, &reason)) autopilot_.on_ins(ins);
      else ++malformed_;
    } else if (channel == channels::kAltimeter) {
      altimeter_t alt;
      if (decode_message(data, size, &alt, &reason)) autopilot_.on_altimeter(alt);
      else ++malformed_;
    } else if (channel == channels::kLcmSelfTest) {
      return;  // the simulator's bus's own; the live bus has its own
    } else if (channel == channels::kStatus && decode_message(data, size, &status_, &reason)) {
      // The simulator's counts are of its own bus, not the live one.
      relabel_relayed_transport_counters(&status_);
      bus_.publish(channel, status_);
      ++relayed_;
    } else {
      bus_.publish_raw(channel, data, size);
      ++relayed_;
    }
  }
  int64_t relayed() const { return relayed_; }
  int64_t malformed() const { return malformed_; }

 private:
  LcmBus& bus_;
  sim_mavlink::SimAutopilot& autopilot_;
  status_t status_;
  int64_t relayed_ = 0;
  int64_t malformed_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Sim-side MAVLink feeder for the sim_mavlink process set: listens to nadir_sim on --sim-lcm-url, sends its "
      "INS as ATTITUDE (or ATTITUDE_QUATERNION) and its ALTIMETER as DISTANCE_SENSOR (facing down) over UDP as an "
      "autopilot would (HEARTBEAT and SYSTEM_TIME at 1 Hz, TIMESYNC answered, boot time = vehicle time since start), "
      "and relays every other channel unchanged onto the live bus. Counts what the companion sends back.",
      "nadir_sim_mavlink"};
  std::string sim_url;
  std::string lcm_url;
  std::string local = "127.0.0.1:14580";
  std::string remote = "127.0.0.1:14540";
  sim_mavlink::SimAutopilotOptions options;
  app.add_option("--sim-lcm-url", sim_url, "LCM URL nadir_sim publishes on (not the live bus)")->required();
  app.add_option("--lcm-url", lcm_url, "live LCM URL (default: $LCM_DEFAULT_URL or udpm with TTL 0)");
  app.add_option("--local", local, "UDP ADDRESS:PORT to bind (the autopilot's end)");
  app.add_option("--remote", remote, "UDP ADDRESS:PORT of the companion (nadir_mavlink_bridge)");
  app.add_flag("--quaternion", options.quaternion, "send ATTITUDE_QUATERNION instead of ATTITUDE");
  app.add_option("--max-distance", options.max_distance_m, "DISTANCE_SENSOR max_distance, m")
      ->check(CLI::Range(1.0, 655.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    LcmBusOptions bus_options;
    bus_options.url = lcm_url;
    LcmBus bus(bus_options);
    lcm::LCM sim(sim_url);
    if (!sim.good()) throw std::runtime_error("cannot start LCM on " + sim_url);
    mavlink_bridge::UdpLink udp(false, local, remote);
    udp.open();
    install_shutdown_handlers();
    auto send = [&](const std::vector<uint8_t>& frame) { udp.send(frame.data(), frame.size()); };
    sim_mavlink::SimAutopilot autopilot(options, vehicle_time_now_us(), send);
    SimRelay relay(bus, autopilot);
    sim.subscribe(".*", &SimRelay::handle, &relay);
    std::fprintf(stderr, "nadir_sim_mavlink: simulator on %s, relaying to %s; MAVLink %s -> %s\n", sim_url.c_str(),
                 bus.url().c_str(), local.c_str(), remote.c_str());
    std::vector<uint8_t> datagram;
    int64_t next_status_us = monotonic_now_us() + 1000000;
    while (!shutdown_requested()) {
      pollfd fds[2] = {{sim.getFileno(), POLLIN, 0}, {udp.fd(), POLLIN, 0}};
      if (::poll(fds, 2, 50) > 0) {
        if (fds[0].revents & POLLIN) sim.handleTimeout(0);
        if (fds[1].revents & POLLIN) {
          while (udp.receive(&datagram)) autopilot.on_datagram(datagram.data(), datagram.size(), vehicle_time_now_us());
        }
      }
      autopilot.tick(vehicle_time_now_us());
      if (monotonic_now_us() >= next_status_us) {
        next_status_us += 1000000;
        StatusReport report;
        report.published = autopilot.sent() + relay.relayed();
        report.errors = udp.send_failures() + relay.malformed();
        for (const auto& [name, count] : autopilot.companion().received) {
          report.counters.emplace_back("companion_" + name, static_cast<double>(count));
        }
        report.counters.emplace_back("companion_rejected_spans",
                                     static_cast<double>(autopilot.companion().rejected_spans));
        bus.publish(channels::kStatus, bus.status_message("sim_mavlink", report));
      }
    }
    std::fprintf(stderr, "nadir_sim_mavlink: stopped: %lld MAVLink frames sent, %lld messages relayed;",
                 static_cast<long long>(autopilot.sent()), static_cast<long long>(relay.relayed()));
    for (const auto& [name, count] : autopilot.companion().received) {
      std::fprintf(stderr, " %s %lld", name.c_str(), static_cast<long long>(count));
    }
    std::fprintf(stderr, "; rejected spans %lld\n", static_cast<long long>(autopilot.companion().rejected_spans));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_sim_mavlink: error: %s\n", e.what());
    return 2;
  }
}
