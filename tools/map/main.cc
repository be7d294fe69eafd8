// nadir_map: reference maps for position fixes. `simulate` writes the
// orthophoto + DEM of the world a simulated flight flies over, seen in
// another season and light (tools/map/simulated_map.h); `check` opens any
// orthophoto + DEM pair with the reader the map matcher uses.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/json_writer.h"
#include "common/paths.h"
#include "processes/sim/flight_profile.h"
#include "tools/map/geotiff_writer.h"
#include "tools/map/map_record.h"
#include "tools/map/raster_ground.h"
#include "tools/map/reference_map.h"
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
  // A profile naming a real place (world:): the map of that place, as nadir_sim flies over it.
  nadir::map::attach_raster_world(&profile, args.seed);
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

struct CheckArgs {
  std::string orthophoto, dem;
  std::vector<double> point;  // latitude, longitude
  bool json = false;
};

void write_raster(nadir::JsonWriter* j, const nadir::map::RasterInfo& r) {
  j->begin_object()
      .field("path", r.path)
      .field("crs", r.crs_name)
      .field("width_px", r.width)
      .field("height_px", r.height)
      .field("bands", r.bands)
      .field("pixel_size_m", r.pixel_size_m)
      .field("nodata_pixels", static_cast<int64_t>(r.nodata_pixels))
      .end_object();
}

// Opens a map pair as the matcher will, and optionally looks a point up.
int check(const CheckArgs& args) {
  const nadir::map::ReferenceMap map = nadir::map::ReferenceMap::open(args.orthophoto, args.dem);
  const nadir::map::RasterInfo& o = map.orthophoto_info();
  const nadir::map::RasterInfo& d = map.dem_info();
  double grey = 0.0, height = 0.0;
  if (args.point.size() == 2) {
    grey = map.sample(args.point[0], args.point[1]);
    height = map.height(args.point[0], args.point[1]);
  }
  if (args.json) {
    nadir::JsonWriter j;
    j.begin_object().key("orthophoto");
    write_raster(&j, o);
    j.key("dem");
    write_raster(&j, d);
    j.field("dem_crs_differs", map.dem_crs_differs());
    if (args.point.size() == 2) j.field("grey", grey).field("height_m", height);
    j.end_object();
    std::printf("%s\n", j.str().c_str());
    return 0;
  }
  for (const nadir::map::RasterInfo* r : {&o, &d})
    std::printf("%s: %d x %d px, %d band(s), %s, %.3f m pixels, %lld NoData/NaN pixels\n", r->path.c_str(), r->width,
                r->height, r->bands, r->crs_name.c_str(), r->pixel_size_m, r->nodata_pixels);
  if (map.dem_crs_differs()) std::printf("the DEM's CRS differs from the orthophoto's: reprojected at every lookup\n");
  if (args.point.size() == 2)
    std::printf("at %.7f, %.7f: grey %.1f, height %.2f m above the WGS84 ellipsoid\n", args.point[0], args.point[1],
                grey, height);
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
  sim->add_option("--max-megapixels", args.options.max_megapixels,
                  "coarsen the gsd (up to 2 m) to keep the map within this many million pixels (0: no limit)")
      ->capture_default_str();
  sim->add_option("--max-gsd", args.options.max_gsd_m, "... but never coarser than this, m (up to 10)")
      ->capture_default_str();
  sim->add_flag("--json", args.json, "print the summary as JSON");
  CheckArgs check_args;
  CLI::App* check_cmd = app.add_subcommand(
      "check", "Opens an orthophoto + DEM pair as the map matcher will (tools/map/reference_map.h) and says what it "
               "found, or why the pair cannot be used (exit 1)");
  check_cmd->add_option("--orthophoto", check_args.orthophoto, "orthophoto GeoTIFF (8-bit grey or RGB)")->required();
  check_cmd->add_option("--dem", check_args.dem, "DEM GeoTIFF (heights above the WGS84 ellipsoid, m)")->required();
  check_cmd->add_option("--point", check_args.point, "LAT LON: look the grey value and height up there")
      ->expected(2);
  check_cmd->add_flag("--json", check_args.json, "machine-readable output");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (sim->parsed()) return simulate(args);
    if (check_cmd->parsed()) return check(check_args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_map: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
