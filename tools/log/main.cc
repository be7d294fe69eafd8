// nadir_log: inspect LCM logs.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

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
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    const nadir::LogSummary summary = nadir::summarize_log(path);
    std::fputs((json ? nadir::log_summary_json(summary) + "\n" : nadir::format_log_summary(summary)).c_str(), stdout);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_log: error: %s\n", e.what());
    return 1;
  }
}
