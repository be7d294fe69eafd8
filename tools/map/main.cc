// nadir_map: reference maps for position fixes. `simulate` writes the
// orthophoto + DEM of the world a simulated flight flies over, seen in
// another season and light (tools/map/simulated_map.h).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/json_writer.h"
#include "common/paths.h"
#include "processes/sim/flight_profile.h"
#include "tools/map/geotiff_writer.h"
#include "tools/map/map_record.h"
#include "tools/map/simulated_map.h"

namespace {

struct SimulateArgs {
  std::string profile;
  uint64_t seed = 1;
  std::string out;
  bool json = false;
  nadir::map::SimulatedMapOptions options;
};

int simulate(const SimulateArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  nadir::sim::FlightProfile profile = nadir::sim::FlightProfile::load(nadir::sim::FlightProfile::resolve(args.profile));
  // map.json names the profile relative to the checkout (same bytes in any checkout).
  const std::string root = nadir::checkout_root() + "/";
  if (profile.source.compare(0, root.size(), root) == 0) profile.source = profile.source.substr(root.size());
  args.options.Check();
  std::filesystem::create_directories(args.out);
  const nadir::map::SimulatedMap map = nadir::map::simulate_map(profile, args.seed, args.options);
  const std::string ortho = args.out + "/orthophoto.tif", dem = args.out + "/dem.tif", record = args.out + "/map.json";
  nadir::map::write_geotiff_byte(ortho, map.grid, map.orthophoto);
  nadir::map::write_geotiff_float(dem, map.grid, map.dem, -9999.0);
  {
    std::ofstream f(record, std::ios::binary);
    f << nadir::map::map_record_json(profile, args.seed, args.options, map);
    if (!f.flush()) throw std::runtime_error(record + ": write failed");
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double width_m = map.grid.width * map.grid.gsd_m, height_m = map.grid.height * map.grid.gsd_m;
  if (args.json) {
    nadir::JsonWriter j;
    j.begin_object()
        .field("out", args.out)
        .field("profile", profile.name)
        .field("seed", static_cast<int64_t>(args.seed))
        .field("crs", "EPSG:" + std::to_string(map.grid.epsg))
        .field("gsd_m", map.grid.gsd_m)
        .field("width_px", map.grid.width)
        .field("height_px", map.grid.height)
        .field("changed_patches", static_cast<int64_t>(map.patches.size()))
        .field("albedo_correlation", map.albedo_correlation)
        .field("seconds", seconds)
        .end_object();
    std::printf("%s\n", j.str().c_str());
  } else {
    std::printf("nadir_map simulate: profile %s seed %llu: %d x %d px at %.2f m (%.0f x %.0f m), EPSG:%d, "
                "%zu changed patches, correlation with the albedo %.3f; %s in %.1f s\n",
                profile.name.c_str(), static_cast<unsigned long long>(args.seed), map.grid.width, map.grid.height,
                map.grid.gsd_m, width_m, height_m, map.grid.epsg, map.patches.size(), map.albedo_correlation,
                args.out.c_str(), seconds);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Reference maps (GeoTIFF orthophoto + DEM) for position fixes.", "nadir_map"};
  app.require_subcommand(1);
  SimulateArgs args;
  CLI::App* sim = app.add_subcommand(
      "simulate", "Writes OUT/orthophoto.tif (8-bit grey), OUT/dem.tif (Float32 ellipsoidal heights) and OUT/map.json: "
                  "the world `nadir_sim --profile P --seed N` flies over, in another season and light, UTM grid");
  sim->add_option("--profile", args.profile, "flight profile: NAME (config/profiles/NAME.yaml) or a YAML file")
      ->required();
  sim->add_option("--seed", args.seed, "the simulator's run seed (the terrain it flies over)")->capture_default_str();
  sim->add_option("--out", args.out, "output folder (created)")->required();
  sim->add_option("--gsd", args.options.gsd_m, "ground sample distance, m (0.5 .. 2)")->capture_default_str();
  sim->add_option("--margin", args.options.margin_m, "around the flight's horizontal extent, m (0 .. 5000)")
      ->capture_default_str();
  sim->add_flag("--json", args.json, "print the summary as JSON");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (sim->parsed()) return simulate(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_map: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
