// nadir_config: the configuration reference generated from the options
// schemas, and a check of a config file against every reader.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>

#include "common/paths.h"
#include "tools/config/config_catalog.h"

int main(int argc, char** argv) {
  CLI::App app{
      "Configuration tool. --config-reference prints (or writes, --out) the configuration reference generated "
      "from every options schema: each key's type, unit, default, allowed range or values and description "
      "(docs/reference/configuration.md is this output). --check reads a config (with overlays and --set "
      "overrides, as the processes take them) through every section's reader and reports the first unknown "
      "key or bad value. Exit 0: done; 2: a configuration error.",
      "nadir_config"};
  bool reference = false;
  bool check = false;
  std::string out_path;
  std::string config_path;
  std::vector<std::string> overlays;
  std::vector<std::string> overrides;
  auto* ref_flag = app.add_flag("--config-reference", reference, "print the configuration reference (Markdown)");
  auto* check_flag = app.add_flag("--check", check, "check a config against every section's reader");
  app.add_option("--out", out_path, "with --config-reference: write it to this file instead of stdout")
      ->needs(ref_flag);
  app.add_option("--config", config_path, "with --check: YAML config (default: <checkout>/config/default.yaml)")
      ->needs(check_flag);
  app.add_option("--config-overlay", overlays, "with --check: YAML fragment merged key by key (repeatable)")
      ->needs(check_flag);
  app.add_option("--set", overrides, "with --check: override a config value: section.key=value (repeatable)")
      ->needs(check_flag);
  ref_flag->excludes(check_flag);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (reference == check) {
    std::fprintf(stderr, "nadir_config: error: give --config-reference or --check (see --help)\n");
    return 2;
  }
  try {
    if (reference) {
      const std::string text = nadir::configuration_reference();
      if (out_path.empty()) {
        std::cout << text;
        return 0;
      }
      std::ofstream out(out_path);
      out << text;
      if (!out) {
        std::fprintf(stderr, "nadir_config: cannot write %s\n", out_path.c_str());
        return 1;
      }
      return 0;
    }
    if (config_path.empty()) config_path = nadir::default_config_path();
    nadir::Config config = nadir::Config::load_file(config_path);
    for (const auto& o : overlays) config.apply_overlay(nadir::Config::load_file(o));
    for (const auto& o : overrides) config.apply_override(o);
    nadir::check_every_section(config);
    std::fprintf(stderr, "nadir_config: %s: every section reads\n", config.source().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_config: error: %s\n", e.what());
    return 2;
  }
}
