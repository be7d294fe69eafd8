// nadir_log: inspect LCM logs.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "tools/log/log_compare.h"
#include "tools/log/log_summary.h"

int main(int argc, char** argv) {
  CLI::App app{"Inspect nadir LCM logs (lcm-logger format).", "nadir_log"};
  app.require_subcommand(1);
  CLI::App* info = app.add_subcommand(
      "info", "Per channel: type, message count, rate, first/last sensor utime, bytes; and damage found");
  std::string path;
  bool json = false;
  info->add_option("FILE", path, "log file")->required();
  info->add_flag("--json", json, "machine-readable output");
  CLI::App* compare = app.add_subcommand(
      "compare", "Compares one channel of two logs message by message (exit 0 when they match within --tolerance)");
  std::string path_b;
  std::string channel = "POSE";
  double tolerance = 1e-9;
  compare->add_option("A", path, "first log")->required();
  compare->add_option("B", path_b, "second log")->required();
  compare->add_option("--channel", channel, "channel to compare")->capture_default_str();
  compare->add_option("--tolerance", tolerance, "largest allowed numeric difference (POSE fields)")
      ->capture_default_str();
  compare->add_flag("--json", json, "machine-readable output");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (compare->parsed()) {
      const nadir::ChannelComparison c = nadir::compare_channel(path, path_b, channel);
      if (json) {
        std::printf("%s\n", nadir::comparison_json(c, tolerance).c_str());
      } else {
        std::printf("%s: %lld vs %lld messages, %lld byte-identical, %lld sensor-time mismatches, max |diff| %g -> %s\n",
                    channel.c_str(), static_cast<long long>(c.count_a), static_cast<long long>(c.count_b),
                    static_cast<long long>(c.identical), static_cast<long long>(c.utime_mismatches),
                    c.max_abs_difference, c.within(tolerance) ? "MATCH" : "DIFFER");
      }
      return c.within(tolerance) ? 0 : 1;
    }
    const nadir::LogSummary summary = nadir::summarize_log(path);
    std::fputs((json ? nadir::log_summary_json(summary) + "\n" : nadir::format_log_summary(summary)).c_str(), stdout);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_log: error: %s\n", e.what());
    return 1;
  }
}
