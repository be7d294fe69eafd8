#include "tools/map/map_record.h"

#include <cmath>
#include <string>

#include "common/json_writer.h"

namespace nadir::map {

std::string map_record_json(const sim::FlightProfile& profile, uint64_t seed, const SimulatedMapOptions& options,
                            const SimulatedMap& map) {
  const MapGrid& g = map.grid;
  JsonWriter j;
  j.begin_object()
      .field("kind", "nadir simulated reference map")
      .field("profile", profile.name)
      .field("profile_source", profile.source)
      .field("seed", static_cast<int64_t>(seed))
      .field("relief_scale", profile.terrain.relief_scale)
      .field("reference_latitude_deg", profile.reference_latitude_deg)
      .field("reference_longitude_deg", profile.reference_longitude_deg)
      .field("reference_height_m", profile.reference_height_m)
      .field("crs", "EPSG:" + std::to_string(g.epsg))
      .field("gsd_m", g.gsd_m)
      .field("margin_m", options.margin_m)
      .field("width_px", g.width)
      .field("height_px", g.height);
  j.key("geotransform").begin_array();
  for (double v : g.geotransform()) j.value(v);
  j.end_array();
  j.key("extent_projected")
      .begin_object()
      .field("x_min", g.x0)
      .field("x_max", g.x0 + g.width * g.gsd_m)
      .field("y_min", g.y0 - g.height * g.gsd_m)
      .field("y_max", g.y0)
      .end_object();
  j.key("extent_local")
      .begin_object()
      .field("north_min", map.north_min)
      .field("north_max", map.north_max)
      .field("east_min", map.east_min)
      .field("east_max", map.east_max)
      .end_object();
  j.key("orthophoto")
      .begin_object()
      .field("file", "orthophoto.tif")
      .field("type", "Byte")
      .field("footprint_subsamples", options.subsamples * options.subsamples)
      .field("albedo_correlation", map.albedo_correlation)
      .end_object();
  j.key("dem")
      .begin_object()
      .field("file", "dem.tif")
      .field("type", "Float32")
      .field("heights", "WGS84 ellipsoidal: reference_height_m + terrain height at the pixel centre")
      .field("nodata", -9999.0)
      .end_object();
  const SeasonTransform& s = options.season;
  j.key("season").begin_object();
  j.field("formula", "v = clamp(0.5 + contrast*(albedo/255 - 0.5) + brightness, 0, 1)^gamma; pixel = 255*v*shade");
  j.field("land_cover_by", "albedo band of the footprint mean");
  j.key("classes").begin_array();
  for (const LandCoverClass& c : s.classes)
    j.begin_object()
        .field("name", c.name)
        .field("albedo_below", c.albedo_below)
        .field("brightness", c.brightness)
        .field("contrast", c.contrast)
        .field("gamma", c.gamma)
        .end_object();
  j.end_array();
  j.field("sun_azimuth_deg", s.sun_azimuth_deg)
      .field("sun_elevation_deg", s.sun_elevation_deg)
      .field("ambient", s.ambient)
      .end_object();
  double area = 0.0;
  for (const ChangedPatch& p : map.patches) area += p.area_m2();
  j.key("changed_patches")
      .begin_object()
      .field("seed", std::to_string(map.patch_seed))
      .field("fraction_requested", options.changed_fraction)
      .field("count", static_cast<int64_t>(map.patches.size()))
      .field("area_m2", area);
  j.key("patches").begin_array();
  for (const ChangedPatch& p : map.patches)
    j.begin_object()
        .field("shape", p.shape == ChangedPatch::kDisc ? "disc" : "rectangle")
        .field("north_m", p.north)
        .field("east_m", p.east)
        .field("half_north_m", p.half_north)
        .field("half_east_m", p.half_east)
        .field("albedo", p.albedo)
        .end_object();
  j.end_array().end_object();
  j.end_object();
  return j.str() + "\n";
}

}  // namespace nadir::map
