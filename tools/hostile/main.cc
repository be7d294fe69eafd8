// nadir_hostile: publishes hostile and faulty messages among a live run's
// real ones (reliability tests; see README "Reliability").
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <exception>
#include <map>
#include <random>
#include <thread>

#include "common/json_writer.h"
#include "common/lcm_bus.h"
#include "common/shutdown.h"
#include "common/time_base.h"
#include "tools/hostile/hostile_messages.h"

int main(int argc, char** argv) {
  CLI::App app{"Publishes hostile and faulty messages on the estimator's channels during a live run: undecodable "
               "bytes, negative and huge length fields, NaN / infinite / impossible values, and valid messages "
               "stamped 10-20 s in the past or the future, cycling through every case. Stamped at the current "
               "vehicle time (host clock), so they land among the real messages. Test networks only.",
               "nadir_hostile"};
  std::string url;
  double rate_hz = 20.0;
  double duration_s = 30.0;
  double delay_s = 0.0;
  uint64_t seed = 1;
  int width = 612, height = 512;
  bool json = false;
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm with TTL 0)");
  app.add_option("--rate", rate_hz, "messages per second")->check(CLI::Range(0.1, 1000.0))->capture_default_str();
  app.add_option("--duration", duration_s, "seconds to publish for")->check(CLI::Range(0.1, 86400.0))
      ->capture_default_str();
  app.add_option("--delay", delay_s, "seconds to wait before the first message")->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--seed", seed, "random bytes and cut points")->capture_default_str();
  app.add_option("--width", width, "image width of the full-size image cases")->check(CLI::Range(1, 10000));
  app.add_option("--height", height, "image height of the full-size image cases")->check(CLI::Range(1, 10000));
  app.add_flag("--json", json, "print the counts per case as JSON at the end");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    nadir::install_shutdown_handlers();
    nadir::LcmBusOptions options;
    options.url = url;
    nadir::LcmBus bus(options);
    std::mt19937_64 rng(seed);
    std::map<std::string, int64_t> sent;
    const int64_t period_us = static_cast<int64_t>(1e6 / rate_hz);
    std::this_thread::sleep_for(std::chrono::microseconds(static_cast<int64_t>(delay_s * 1e6)));
    const int64_t start = nadir::monotonic_now_us();
    const int64_t end = start + static_cast<int64_t>(duration_s * 1e6);
    size_t index = 0;
    for (int64_t next = start; next < end && !nadir::shutdown_requested(); next += period_us, ++index) {
      const int64_t wait = next - nadir::monotonic_now_us();
      if (wait > 0) std::this_thread::sleep_for(std::chrono::microseconds(wait));
      const nadir::HostileMessage m = nadir::hostile_message(index, nadir::vehicle_time_now_us(), width, height, rng);
      bus.publish_raw(m.channel, m.bytes.data(), m.bytes.size());
      ++sent[m.kind];
    }
    int64_t total = 0;
    for (const auto& [kind, n] : sent) total += n;
    if (json) {
      nadir::JsonWriter j;
      j.begin_object().field("sent", total).key("per_case").begin_object();
      for (const auto& [kind, n] : sent) j.field(kind, n);
      j.end_object().end_object();
      std::printf("%s\n", j.str().c_str());
    } else {
      std::printf("nadir_hostile: sent %lld messages in %zu cases\n", static_cast<long long>(total), sent.size());
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_hostile: error: %s\n", e.what());
    return 1;
  }
}
