// nadir_status: live table of the STATUS channel, one row per process.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <exception>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/shutdown.h"
#include "common/time_base.h"
#include "tools/status/status_table.h"

int main(int argc, char** argv) {
  CLI::App app{"Shows every nadir process's STATUS: alive/stale, message rates, drops, errors, latency.",
               "nadir_status"};
  std::string url;
  bool once = false;
  bool json = false;
  double listen_s = 2.5;
  double stale_s = 3.0;
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm with TTL 0)");
  app.add_flag("--once", once, "listen for --listen seconds, print once and exit");
  app.add_flag("--json", json, "with --once: print JSON (an array of processes)");
  app.add_option("--listen", listen_s, "seconds to listen with --once")->check(CLI::Range(0.1, 600.0));
  app.add_option("--stale", stale_s, "a process unheard for this long is STALE")->check(CLI::Range(0.5, 600.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (json && !once) {
    std::fprintf(stderr, "nadir_status: error: --json needs --once\n");
    return 2;
  }
  try {
    nadir::LcmBusOptions options;
    options.url = url;
    nadir::LcmBus bus(options);
    nadir::StatusTable table(stale_s);
    bus.subscribe<nadir::status_t>(nadir::channels::kStatus, [&](const nadir::status_t& s) {
      table.update(s, nadir::monotonic_now_us());
    });
    nadir::install_shutdown_handlers();
    const int64_t start = nadir::monotonic_now_us();
    int64_t next_draw = start;
    const bool terminal = isatty(STDOUT_FILENO) == 1;
    while (!nadir::shutdown_requested()) {
      bus.handle(100);
      const int64_t now = nadir::monotonic_now_us();
      if (once) {
        if (nadir::us_to_s(now - start) >= listen_s) {
          std::printf("%s\n", json ? table.json(now).c_str() : table.format(now).c_str());
          return 0;
        }
        continue;
      }
      if (now >= next_draw) {
        if (terminal) std::printf("\033[H\033[2J");
        std::printf("nadir_status on %s\n%s\n", bus.url().c_str(), table.format(now).c_str());
        std::fflush(stdout);
        next_draw = now + 1000000;
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_status: error: %s\n", e.what());
    return 1;
  }
}
