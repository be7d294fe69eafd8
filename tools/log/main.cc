// nadir_log: inspect LCM logs.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>

#include "tools/log/log_compare.h"
#include "tools/log/log_dump.h"
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
  CLI::App* dump = app.add_subcommand(
      "dump", "Writes one channel as CSV (one row per message; TRACKS: one row per track; VO_GROUND: one row per "
              "point) or JSON lines; types: TRACKS, VO_DELTA, VO_GROUND, INS, ALTIMETER, POSE, GROUND_TRUTH "
              "(recognised by fingerprint, any channel name)");
  std::string dump_channel_name;
  std::string output;
  dump->add_option("FILE", path, "log file")->required();
  dump->add_option("CHANNEL", dump_channel_name, "channel, e.g. TRACKS or VO_DELTA")->required();
  dump->add_flag("--json", json, "JSON lines (one object per row) instead of CSV");
  dump->add_option("-o,--output", output, "write to this file instead of stdout");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (dump->parsed()) {
      std::ofstream file;
      if (!output.empty()) {
        file.open(output);
        if (!file) {
          std::fprintf(stderr, "nadir_log: error: %s: cannot create\n", output.c_str());
          return 1;
        }
      }
      const nadir::DumpStats s = nadir::dump_channel(path, dump_channel_name,
                                                     json ? nadir::DumpFormat::kJsonLines : nadir::DumpFormat::kCsv,
                                                     output.empty() ? std::cout : file);
      std::cout.flush();
      std::fprintf(stderr, "nadir_log dump: %s: channel %s (%s): %lld message(s), %lld row(s); skipped %lld corrupt "
                   "record(s)%s, %lld undecodable message(s)\n", path.c_str(), dump_channel_name.c_str(),
                   s.type.c_str(), static_cast<long long>(s.messages), static_cast<long long>(s.rows),
                   static_cast<long long>(s.corrupt_records), s.truncated ? " (truncated)" : "",
                   static_cast<long long>(s.undecodable));
      if (!s.first_decode_error.empty()) std::fprintf(stderr, "  first undecodable: %s\n", s.first_decode_error.c_str());
      std::fputs(s.damage_report.c_str(), stderr);
      if (!output.empty() && !(file.flush())) {
        std::fprintf(stderr, "nadir_log: error: %s: write failed\n", output.c_str());
        return 1;
      }
      return 0;
    }
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
