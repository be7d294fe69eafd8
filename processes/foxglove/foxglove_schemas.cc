#include "processes/foxglove/foxglove_schemas.h"

#include <nlohmann/json.hpp>

#include <stdexcept>

namespace nadir::foxglove_schemas {
namespace {

using nlohmann::json;

json number() { return {{"type", "number"}}; }
json integer() { return {{"type", "integer"}}; }
json string() { return {{"type", "string"}}; }
json array_of(json items) { return {{"type", "array"}, {"items", std::move(items)}}; }

json object(const std::string& title, json properties) {
  json required = json::array();
  for (auto it = properties.begin(); it != properties.end(); ++it) required.push_back(it.key());
  return {{"title", title}, {"type", "object"}, {"properties", std::move(properties)}, {"required", required}};
}

json time() {
  return object("time", {{"sec", {{"type", "integer"}, {"minimum", 0}}},
                         {"nsec", {{"type", "integer"}, {"minimum", 0}, {"maximum", 999999999}}}});
}
json vector3() { return object("foxglove.Vector3", {{"x", number()}, {"y", number()}, {"z", number()}}); }
json quaternion() {
  return object("foxglove.Quaternion", {{"x", number()}, {"y", number()}, {"z", number()}, {"w", number()}});
}
json point2() { return object("foxglove.Point2", {{"x", number()}, {"y", number()}}); }
json color() { return object("foxglove.Color", {{"r", number()}, {"g", number()}, {"b", number()}, {"a", number()}}); }

json location_fix() {
  json s = object("foxglove.LocationFix", {{"timestamp", time()},
                                           {"frame_id", string()},
                                           {"latitude", number()},
                                           {"longitude", number()},
                                           {"altitude", number()},
                                           {"position_covariance", array_of(number())},
                                           {"position_covariance_type", integer()}});
  s["properties"]["position_covariance"]["minItems"] = 9;
  s["properties"]["position_covariance"]["maxItems"] = 9;
  s["description"] = "Geodetic position; covariance in m^2, East-North-Up, row-major";
  return s;
}

json pose_in_frame() {
  return object("foxglove.PoseInFrame",
                {{"timestamp", time()},
                 {"frame_id", string()},
                 {"pose", object("foxglove.Pose", {{"position", vector3()}, {"orientation", quaternion()}})}});
}

json frame_transform() {
  return object("foxglove.FrameTransform", {{"timestamp", time()},
                                            {"parent_frame_id", string()},
                                            {"child_frame_id", string()},
                                            {"translation", vector3()},
                                            {"rotation", quaternion()}});
}

json raw_image() {
  json s = object("foxglove.RawImage", {{"timestamp", time()},
                                        {"frame_id", string()},
                                        {"width", integer()},
                                        {"height", integer()},
                                        {"encoding", string()},
                                        {"step", integer()},
                                        {"data", string()}});
  s["properties"]["data"]["contentEncoding"] = "base64";
  return s;
}

json point_cloud() {
  const json field = object("foxglove.PackedElementField",
                            {{"name", string()}, {"offset", {{"type", "integer"}, {"minimum", 0}}}, {"type", integer()}});
  json s = object("foxglove.PointCloud",
                  {{"timestamp", time()},
                   {"frame_id", string()},
                   {"pose", object("foxglove.Pose", {{"position", vector3()}, {"orientation", quaternion()}})},
                   {"point_stride", {{"type", "integer"}, {"minimum", 0}}},
                   {"fields", array_of(field)},
                   {"data", string()}});
  s["properties"]["data"]["contentEncoding"] = "base64";
  s["description"] = "Points in frame_id, packed little-endian: x, y, z, depth_sigma (float32, m)";
  return s;
}

json image_annotations() {
  const json points = object("foxglove.PointsAnnotation", {{"timestamp", time()},
                                                          {"type", integer()},
                                                          {"points", array_of(point2())},
                                                          {"outline_color", color()},
                                                          {"outline_colors", array_of(color())},
                                                          {"fill_color", color()},
                                                          {"thickness", number()}});
  const json circle = object("foxglove.CircleAnnotation", {{"timestamp", time()},
                                                           {"position", point2()},
                                                           {"diameter", number()},
                                                           {"thickness", number()},
                                                           {"fill_color", color()},
                                                           {"outline_color", color()}});
  const json text = object("foxglove.TextAnnotation", {{"timestamp", time()},
                                                       {"position", point2()},
                                                       {"text", string()},
                                                       {"font_size", number()},
                                                       {"text_color", color()},
                                                       {"background_color", color()}});
  return object("foxglove.ImageAnnotations",
                {{"circles", array_of(circle)}, {"points", array_of(points)}, {"texts", array_of(text)}});
}

// nadir's plain views: every field a number unless listed otherwise.
json plain(const std::string& title, std::initializer_list<const char*> numbers,
           std::initializer_list<const char*> strings = {}) {
  json properties = json::object();
  properties["timestamp"] = time();
  for (const char* n : numbers) properties[n] = number();
  for (const char* s : strings) properties[s] = string();
  return object(title, properties);
}

json named_schema(const std::string& name) {
  if (name == "foxglove.LocationFix") return location_fix();
  if (name == "foxglove.PoseInFrame") return pose_in_frame();
  if (name == "foxglove.FrameTransform") return frame_transform();
  if (name == "foxglove.RawImage") return raw_image();
  if (name == "foxglove.ImageAnnotations") return image_annotations();
  if (name == "foxglove.PointCloud") return point_cloud();
  if (name == "nadir.Pose")
    return plain(name, {"utime", "north_m", "east_m", "down_m", "velocity_n", "velocity_e", "velocity_d", "roll_deg",
                        "pitch_deg", "yaw_deg", "height_agl_m", "sigma_north_m", "sigma_east_m", "sigma_down_m",
                        "sigma_yaw_deg", "protection_level_m", "flags", "flag_vo_gap", "flag_ins_yaw_rejected",
                        "flag_no_altimeter", "flag_initializing", "flag_coasting", "frames"});
  if (name == "nadir.GroundTruth")
    return plain(name, {"utime", "kind", "north_m", "east_m", "down_m", "velocity_n", "velocity_e", "velocity_d",
                        "roll_deg", "pitch_deg", "yaw_deg", "height_agl_m", "terrain_height_m"});
  if (name == "nadir.VoDelta")
    return plain(name,
                 {"utime", "prev_utime", "dx", "dy", "dz", "dyaw_deg", "ground_roll_deg", "ground_pitch_deg",
                  "sigma_dx", "sigma_dy", "sigma_dz", "sigma_dyaw_deg", "altitude_m", "inliers", "outliers",
                  "residual_rms_px", "iterations", "quality", "quality_too_few_features", "quality_no_altimeter",
                  "quality_stale_altimeter", "quality_not_converged", "quality_no_attitude", "quality_frame_gap",
                  "quality_high_residual", "quality_depth_layers",
                  "quality_heading_contradicts"},
                 {"variant"});
  if (name == "nadir.Ins")
    return plain(name, {"utime", "device_utime", "roll_deg", "pitch_deg", "yaw_deg", "latitude_deg", "longitude_deg",
                        "height_m", "velocity_n", "velocity_e", "velocity_d", "ins_status", "flags"});
  if (name == "nadir.Altimeter")
    return plain(name, {"utime", "range_m", "beam_x", "beam_y", "beam_z", "signal_quality", "validity"});
  if (name == "nadir.Trigger") return plain(name, {"utime", "device_utime", "sequence", "edge", "flags"});
  if (name == "nadir.Config") return plain(name, {"utime"}, {"name", "source", "yaml"});
  if (name == "nadir.Status") {
    json s = plain(name,
                   {"utime", "pid", "state", "received", "published", "dropped", "errors", "malformed",
                    "latency_p50_ms", "latency_p99_ms", "latency_max_ms"},
                   {"name", "state_name", "detail"});
    // Counters differ per process: an object of name -> number.
    s["properties"]["counters"] = {{"type", "object"}, {"additionalProperties", number()}};
    s["required"].push_back("counters");
    return s;
  }
  if (name == "nadir.TrackStats")
    return plain(name, {"utime", "prev_utime", "frame_counter", "flags", "num_tracks", "mean_age", "mean_flow_px"});
  throw std::invalid_argument("foxglove schema '" + name + "' is not defined");
}

}  // namespace

std::string schema_text(const std::string& schema_name) { return named_schema(schema_name).dump(); }

}  // namespace nadir::foxglove_schemas
