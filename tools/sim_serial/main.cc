// nadir_sim_serial: the INS and the laser altimeter of a simulated flight on
// pseudo-terminals, byte for byte as the real devices send them, at their
// rates, so nadir_ins_bridge runs unchanged on a flight with ground truth.

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <exception>
#include <memory>
#include <queue>
#include <vector>
#include <thread>

#include "common/config.h"
#include "common/geometry.h"
#include "common/paths.h"
#include "common/shutdown.h"
#include "common/time_base.h"
#include "processes/ins_bridge/bridge_options.h"
#include "common/gps_time.h"
#include "processes/ins_bridge/pseudo_terminal.h"
#include "tools/sim_serial/device_formatter.h"
#include "tools/sim_serial/flight_source.h"

int main(int argc, char** argv) {
  using namespace nadir;
  CLI::App app{
      "Creates two pseudo-terminals and writes a flight into them as a NovAtel SPAN receiver (INSPVAA / "
      "INSPVASA / INSPVAB, INSSTDEVA at 1 Hz) and a LightWare-style laser altimeter would, at the sample "
      "rates. The flight comes from a simulator LCM log (INS and ALTIMETER channels) or is generated (a "
      "coordinated circle over flat ground). Point nadir_ins_bridge at the printed paths or at the "
      "--ins-link / --altimeter-link symlinks.",
      "nadir_sim_serial"};
  std::string config_path, log_path, ins_link, alt_link, format_name = "mixed", time_mode = "now";
  double speed = 1.0;
  bool no_stddev = false;
  double linger_s = 0.5, start_delay_s = 0.0;
  int64_t log_origin_us = 0, vehicle_origin_us = 0;
  sim_serial::GeneratedFlightOptions generated;
  app.add_option("--config", config_path, "YAML config (default: <checkout>/config/default.yaml): IMU mount, beam");
  app.add_option("--log", log_path, "simulator LCM log to read INS and ALTIMETER from (default: generate a flight)");
  app.add_option("--ins-link", ins_link, "create a symlink to the INS pty here (e.g. logs/sim_ins)");
  app.add_option("--altimeter-link", alt_link, "create a symlink to the altimeter pty here (e.g. logs/sim_alt)");
  app.add_option("--ins-format", format_name, "ascii (INSPVAA) | short (INSPVASA) | binary (INSPVAB) | mixed")
      ->check(CLI::IsMember({"ascii", "short", "binary", "mixed"}));
  app.add_flag("--no-stddev", no_stddev, "do not write INSSTDEVA");
  app.add_option("--speed", speed, "playback speed factor (device time always follows the wall clock)")
      ->check(CLI::Range(0.01, 100.0));
  app.add_option("--time", time_mode, "GPS time: now (from the host clock) | log (the log's device time)")
      ->check(CLI::IsMember({"now", "log"}));
  app.add_option("--duration", generated.duration_s, "generated flight length, s")->check(CLI::Range(0.1, 1e6));
  app.add_option("--ins-rate", generated.ins_rate_hz, "generated INS rate, Hz")->check(CLI::Range(1.0, 1000.0));
  app.add_option("--altimeter-rate", generated.altimeter_rate_hz, "generated altimeter rate, Hz")
      ->check(CLI::Range(0.1, 1000.0));
  app.add_option("--height-agl", generated.height_agl_m, "generated flight height above ground, m");
  app.add_option("--seed", generated.seed, "generated altimeter noise seed");
  app.add_option("--log-origin-us", log_origin_us, "log utime played at --vehicle-origin-us");
  app.add_option("--vehicle-origin-us", vehicle_origin_us,
                 "vehicle time (us) at which log utime --log-origin-us is played (with --time now); lets "
                 "several players of one log (e.g. nadir_fake_camera --paced) share one clock");
  app.add_option("--start-delay", start_delay_s, "seconds between creating the ptys and the first sample")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--linger", linger_s,
                 "seconds the ptys stay open after the flight so the reader drains them (-1: until SIGINT)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (config_path.empty()) config_path = default_config_path();
    const Config config = Config::load_file(config_path);
    const ins_bridge::BridgeOptions bridge = ins_bridge::BridgeOptions::from_config(config);
    for (int i = 0; i < 3; ++i) generated.beam_body[i] = bridge.altimeter.beam_body[i];
    sim_serial::InsFormat format;
    sim_serial::parse_ins_format(format_name, &format);
    const Eigen::Vector3d mount(deg_to_rad(bridge.ins.imu_to_body_rpy_deg.x()),
                                deg_to_rad(bridge.ins.imu_to_body_rpy_deg.y()),
                                deg_to_rad(bridge.ins.imu_to_body_rpy_deg.z()));
    sim_serial::DeviceFormatter formatter(format, mount, !no_stddev);
    std::unique_ptr<sim_serial::FlightSource> source =
        log_path.empty() ? sim_serial::make_generated_source(generated) : sim_serial::make_log_source(log_path);

    ins_bridge::PseudoTerminal ins_pty(ins_link);
    ins_bridge::PseudoTerminal alt_pty(alt_link);
    std::printf("INS %s%s%s\nALTIMETER %s%s%s\n", ins_pty.slave_path().c_str(), ins_link.empty() ? "" : " <- ",
                ins_link.c_str(), alt_pty.slave_path().c_str(), alt_link.empty() ? "" : " <- ", alt_link.c_str());
    std::fflush(stdout);
    std::fprintf(stderr, "nadir_sim_serial: %s, INS format %s, speed %.2f\n", source->describe().c_str(),
                 format_name.c_str(), speed);
    install_shutdown_handlers();

    using Clock = std::chrono::steady_clock;
    const auto delay_end = Clock::now() + std::chrono::microseconds(static_cast<int64_t>(start_delay_s * 1e6));
    while (Clock::now() < delay_end && !shutdown_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    bool have_t0 = false;
    int64_t t0 = 0;
    if (vehicle_origin_us != 0) {
      // Shared clock: log time t is played at vehicle_origin + (t - log_origin) / speed.
      if (vehicle_origin_us < vehicle_time_now_us()) throw std::invalid_argument("--vehicle-origin-us is in the past");
      while (vehicle_time_now_us() < vehicle_origin_us && !shutdown_requested()) {
        std::this_thread::sleep_for(std::chrono::microseconds(
            std::min<int64_t>(10000, std::max<int64_t>(1, vehicle_origin_us - vehicle_time_now_us()))));
      }
      have_t0 = true;
      t0 = log_origin_us;
    }
    const auto start = Clock::now();
    const int64_t start_unix_us = vehicle_origin_us != 0 ? vehicle_origin_us : vehicle_time_now_us();
    int64_t ins_written = 0, alt_written = 0, dropped = 0, bytes = 0, last_gps_us = -1;
    auto next_report = start + std::chrono::seconds(10);
    // A real device's bytes are on the line for size * character time after
    // the measurement, and a line is busy while it sends. Each write happens
    // when its last byte would have arrived, so the bridge's reconstruction of
    // the first byte's arrival lands on the sample's time.
    struct PendingWrite {
      int64_t at_us;  // since start
      bool ins;
      std::vector<uint8_t> bytes;
      bool operator>(const PendingWrite& other) const { return at_us > other.at_us; }
    };
    std::priority_queue<PendingWrite, std::vector<PendingWrite>, std::greater<PendingWrite>> pending;
    int64_t ins_line_free_us = 0, alt_line_free_us = 0;
    const double ins_byte_us = bridge.ins.serial.byte_time_us();
    const double alt_byte_us = bridge.altimeter.serial.byte_time_us();
    sim_serial::Sample sample;
    bool source_done = false;
    while (!shutdown_requested()) {
      // Read ahead until every sample that could be written before the earliest pending write is queued.
      while (!source_done && (pending.empty() || !have_t0 ||
                              static_cast<double>(sample.t_us - t0) / speed <= static_cast<double>(pending.top().at_us))) {
        if (!source->next(&sample)) {
          source_done = true;
          break;
        }
        if (!have_t0) {
          t0 = sample.t_us;
          have_t0 = true;
        }
        const int64_t since_us = static_cast<int64_t>(static_cast<double>(sample.t_us - t0) / speed);
        PendingWrite write;
        write.ins = sample.kind == sim_serial::Sample::Kind::kIns;
        if (write.ins) {
          int64_t gps_us = time_mode == "log" && sample.ins.device_utime > 0
                               ? sample.ins.device_utime
                               : unix_to_gps_us(start_unix_us + since_us);
          if (gps_us <= last_gps_us) gps_us = last_gps_us + 1;  // the receiver's clock never repeats
          last_gps_us = gps_us;
          write.bytes = formatter.ins_bytes(sample.ins, gps_us);
        } else {
          const std::string line = sim_serial::DeviceFormatter::altimeter_line(sample.altimeter);
          write.bytes.assign(line.begin(), line.end());
        }
        int64_t& line_free = write.ins ? ins_line_free_us : alt_line_free_us;
        const double byte_us = write.ins ? ins_byte_us : alt_byte_us;
        write.at_us = std::max(since_us, line_free) + std::llround(static_cast<double>(write.bytes.size()) * byte_us);
        line_free = write.at_us;
        pending.push(std::move(write));
      }
      if (pending.empty()) break;
      const PendingWrite& next = pending.top();
      const auto due = start + std::chrono::microseconds(next.at_us);
      while (Clock::now() < due && !shutdown_requested())
        std::this_thread::sleep_until(std::min(due, Clock::now() + std::chrono::milliseconds(100)));
      ins_bridge::PseudoTerminal& pty = next.ins ? ins_pty : alt_pty;
      const size_t n = pty.write(next.bytes.data(), next.bytes.size());
      bytes += static_cast<int64_t>(n);
      if (n < next.bytes.size()) ++dropped;
      else if (next.ins) ++ins_written;
      else ++alt_written;
      pending.pop();
      if (Clock::now() >= next_report) {
        std::fprintf(stderr, "nadir_sim_serial: INS %lld, altimeter %lld, dropped (pty full) %lld\n",
                     static_cast<long long>(ins_written), static_cast<long long>(alt_written),
                     static_cast<long long>(dropped));
        next_report += std::chrono::seconds(10);
      }
    }
    std::fprintf(stderr, "nadir_sim_serial: done: INS %lld, altimeter %lld, dropped (pty full) %lld, %lld bytes\n",
                 static_cast<long long>(ins_written), static_cast<long long>(alt_written),
                 static_cast<long long>(dropped), static_cast<long long>(bytes));
    const auto linger_end = Clock::now() + std::chrono::microseconds(static_cast<int64_t>(linger_s * 1e6));
    while (!shutdown_requested() && (linger_s < 0 || Clock::now() < linger_end))
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!ins_link.empty()) std::remove(ins_link.c_str());
    if (!alt_link.empty()) std::remove(alt_link.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_sim_serial: error: %s\n", e.what());
    return 2;
  }
}
