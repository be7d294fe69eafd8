#include "processes/foxglove/foxglove_translator.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/channels.h"
#include "common/message_guard.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/ground_points_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/status_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/trigger_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir {
namespace {

using nlohmann::json;
namespace ch = channels;

constexpr double kDeg = 180.0 / M_PI;

json stamp(int64_t utime) {
  const int64_t t = std::max<int64_t>(utime, 0);
  return {{"sec", t / 1000000}, {"nsec", (t % 1000000) * 1000}};
}

// Body (forward-right-down) in NED -> body (forward-left-up) in ENU.
Eigen::Quaterniond enu_flu_orientation(double roll, double pitch, double yaw) {
  const Eigen::Matrix3d ned_frd = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                      .toRotationMatrix();
  Eigen::Matrix3d enu_ned;
  enu_ned << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const Eigen::Matrix3d frd_flu = Eigen::Vector3d(1, -1, -1).asDiagonal();
  Eigen::Quaterniond q(enu_ned * ned_frd * frd_flu);
  q.normalize();
  return q;
}

json xyz(double x, double y, double z) { return {{"x", x}, {"y", y}, {"z", z}}; }
json quat(const Eigen::Quaterniond& q) { return {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}}; }
json rgba(double r, double g, double b, double a) { return {{"r", r}, {"g", g}, {"b", b}, {"a", a}}; }
double sigma(double variance) { return variance > 0 ? std::sqrt(variance) : 0.0; }
int bit(int32_t flags, int32_t mask) { return (flags & mask) ? 1 : 0; }

const char* state_name(int8_t state) {
  switch (state) {
    case status_t::STATE_STARTING: return "STARTING";
    case status_t::STATE_OK: return "OK";
    case status_t::STATE_WARN: return "WARN";
    case status_t::STATE_ERROR: return "ERROR";
    case status_t::STATE_STOPPING: return "STOPPING";
  }
  return "UNKNOWN";
}

// The Map, 3-D and plain views of one body pose (estimate or truth).
struct PoseViews {
  json fix, pose, tf;
};

PoseViews pose_views(GeodeticTrack* track, int64_t utime, const double ned[3], double roll, double pitch,
                     double yaw, const double (*covariance)[3], const std::string& child_frame) {
  PoseViews v;
  const GeodeticPoint g = track->geodetic(Eigen::Vector3d(ned[0], ned[1], ned[2]));
  json cov = json::array();
  int type = 0;  // UNKNOWN
  if (covariance) {
    // NED -> ENU: swap north/east, negate down.
    const int axis[3] = {1, 0, 2};
    const double sign[3] = {1, 1, -1};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) cov.push_back(sign[r] * sign[c] * covariance[axis[r]][axis[c]]);
    type = 3;  // KNOWN
  } else {
    for (int i = 0; i < 9; ++i) cov.push_back(0.0);
  }
  v.fix = {{"timestamp", stamp(utime)}, {"frame_id", child_frame}, {"latitude", g.latitude_deg},
           {"longitude", g.longitude_deg}, {"altitude", g.height_m}, {"position_covariance", cov},
           {"position_covariance_type", type}};
  const Eigen::Quaterniond q = enu_flu_orientation(roll, pitch, yaw);
  const json position = xyz(ned[1], ned[0], -ned[2]);
  v.pose = {{"timestamp", stamp(utime)},
            {"frame_id", "map"},
            {"pose", {{"position", position}, {"orientation", quat(q)}}}};
  v.tf = {{"timestamp", stamp(utime)}, {"parent_frame_id", "map"}, {"child_frame_id", child_frame},
          {"translation", position}, {"rotation", quat(q)}};
  return v;
}

// Truth samples kept until the first POSE: 2.5 s of the simulator's 100 Hz.
constexpr size_t kRecentTruth = 256;

// The truth at `utime`: interpolated between the samples around it (in any
// arrival order), else the nearest.
template <typename Samples>
Eigen::Vector3d truth_near(const Samples& samples, int64_t utime) {
  const auto* before = &samples.front();
  const auto* after = &samples.front();
  bool have_before = false, have_after = false;
  for (const auto& s : samples) {
    if (s.utime <= utime && (!have_before || s.utime > before->utime)) before = &s, have_before = true;
    if (s.utime >= utime && (!have_after || s.utime < after->utime)) after = &s, have_after = true;
  }
  if (!have_before) return after->ned;
  if (!have_after || after->utime == before->utime) return before->ned;
  const double w = static_cast<double>(utime - before->utime) / static_cast<double>(after->utime - before->utime);
  return before->ned + w * (after->ned - before->ned);
}

std::string base64(const uint8_t* data, size_t size) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const uint32_t n = (uint32_t{data[i]} << 16) | (uint32_t{data[i + 1]} << 8) | data[i + 2];
    out += table[n >> 18];
    out += table[(n >> 12) & 63];
    out += table[(n >> 6) & 63];
    out += table[n & 63];
  }
  if (i < size) {
    uint32_t n = uint32_t{data[i]} << 16;
    if (i + 1 < size) n |= uint32_t{data[i + 1]} << 8;
    out += table[n >> 18];
    out += table[(n >> 12) & 63];
    out += i + 1 < size ? table[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// VO_GROUND as a point cloud in base_link_level (the frame's level frame,
// forward-left-up: the message's forward-right-down with y and z negated):
// x, y, z and the depth's sigma as little-endian float32, 16 bytes a point.
json ground_point_cloud(const ground_points_t& m) {
  constexpr int kFloats = 4;
  std::vector<uint8_t> bytes(static_cast<size_t>(m.num_points) * kFloats * sizeof(float));
  for (int i = 0; i < m.num_points; ++i) {
    const float point[kFloats] = {m.position_m[i][0], -m.position_m[i][1], -m.position_m[i][2], m.depth_sigma_m[i]};
    std::memcpy(bytes.data() + static_cast<size_t>(i) * sizeof(point), point, sizeof(point));
  }
  json fields = json::array();
  const char* names[kFloats] = {"x", "y", "z", "depth_sigma"};
  for (int f = 0; f < kFloats; ++f)
    fields.push_back({{"name", names[f]}, {"offset", f * static_cast<int>(sizeof(float))}, {"type", 7}});  // FLOAT32
  return json{{"timestamp", stamp(m.utime)},
              {"frame_id", "base_link_level"},
              {"pose", {{"position", xyz(0, 0, 0)}, {"orientation", quat(Eigen::Quaterniond::Identity())}}},
              {"point_stride", kFloats * static_cast<int>(sizeof(float))},
              {"fields", fields},
              {"data", base64(bytes.data(), bytes.size())}};
}

}  // namespace

FoxgloveTranslator::FoxgloveTranslator(const FoxgloveTranslatorOptions& options)
    : options_(options), pose_track_(options.origin), truth_track_(options.origin), origin_known_(!options.origin_from_ins) {
  topics_ = {
      {"POSE", ch::kPose, "nadir.Pose"},
      {"POSE/fix", ch::kPose, "foxglove.LocationFix"},
      {"POSE/pose", ch::kPose, "foxglove.PoseInFrame"},
      {"POSE/tf", ch::kPose, "foxglove.FrameTransform"},
      {"POSE/level_tf", ch::kPose, "foxglove.FrameTransform"},
      {"GROUND_TRUTH", ch::kGroundTruth, "nadir.GroundTruth"},
      {"GROUND_TRUTH/fix", ch::kGroundTruth, "foxglove.LocationFix"},
      {"GROUND_TRUTH/pose", ch::kGroundTruth, "foxglove.PoseInFrame"},
      {"GROUND_TRUTH/tf", ch::kGroundTruth, "foxglove.FrameTransform"},
      {"CAMERA_IMAGE", ch::kCameraImage, "foxglove.RawImage"},
      {"TRACKS", ch::kTracks, "foxglove.ImageAnnotations"},
      {"TRACKS/stats", ch::kTracks, "nadir.TrackStats"},
      {"VO_DELTA", ch::kVoDelta, "nadir.VoDelta"},
      {"VO_GROUND", ch::kVoGround, "foxglove.PointCloud"},
      {"STATUS", ch::kStatus, "nadir.Status"},
      {"INS", ch::kIns, "nadir.Ins"},
      {"ALTIMETER", ch::kAltimeter, "nadir.Altimeter"},
      {"CAMERA_TRIGGER", ch::kCameraTrigger, "nadir.Trigger"},
      {"CONFIG", ch::kConfig, "nadir.Config"},
  };
}

std::vector<std::string> FoxgloveTranslator::lcm_channels() const {
  std::vector<std::string> out;
  for (const FoxgloveTopic& t : topics_)
    if (out.empty() || out.back() != t.lcm_channel) out.push_back(t.lcm_channel);
  return out;
}

bool FoxgloveTranslator::translate(const std::string& channel, const uint8_t* data, size_t size,
                                   const std::function<bool(int)>& wanted, std::vector<FoxgloveMessage>* out,
                                   std::string* reason) {
  auto want = [&](int topic) { return !wanted || wanted(topic); };
  auto topic_index = [&](const char* name) {
    for (size_t i = 0; i < topics_.size(); ++i)
      if (topics_[i].name == name) return static_cast<int>(i);
    return -1;
  };
  auto emit = [&](const char* name, int64_t utime, const std::function<json()>& make) {
    const int topic = topic_index(name);
    if (topic < 0 || !want(topic)) return;
    out->push_back({topic, utime * 1000, make().dump(-1, ' ', false, json::error_handler_t::replace)});
  };
  auto any_wanted = [&](const std::string& lcm_channel) {
    for (size_t i = 0; i < topics_.size(); ++i)
      if (topics_[i].lcm_channel == lcm_channel && want(static_cast<int>(i))) return true;
    return false;
  };
  if (!origin_known_ && channel == ch::kIns) {
    ins_t m;
    std::string ignored;  // an INS that does not decode is reported on its own topic
    if (decode_message(data, size, &m, &ignored)) pose_origin_.add_ins(m);
  }
  if (!truth_origin_known_ && channel == ch::kGroundTruth) {
    ground_truth_t m;
    std::string ignored;  // a truth that does not decode is reported on its own topic
    if (decode_message(data, size, &m, &ignored)) {
      recent_truth_.push_back({m.utime, Eigen::Vector3d(m.position_ned[0], m.position_ned[1], m.position_ned[2])});
      if (recent_truth_.size() > kRecentTruth) recent_truth_.pop_front();
    }
  }
  if (!origin_known_ && channel == ch::kPose) {
    pose_t m;
    std::string ignored;  // a POSE that does not decode is reported below
    if (decode_message(data, size, &m, &ignored)) pose_origin_.add_pose(m);
  }
  if (!origin_known_ && pose_origin_.known()) {
    pose_track_ = truth_track_ = GeodeticTrack(pose_origin_.origin());
    origin_known_ = true;
  }
  if (!truth_origin_known_ && channel == ch::kPose && !recent_truth_.empty()) {
    pose_t m;
    std::string ignored;
    if (decode_message(data, size, &m, &ignored)) {
      truth_offset_ned_ = truth_near(recent_truth_, m.utime) -
                          Eigen::Vector3d(m.position_ned[0], m.position_ned[1], m.position_ned[2]);
      truth_origin_known_ = true;
      recent_truth_.clear();
    }
  }
  if (!any_wanted(channel)) return true;  // no topic, or nobody listening: not even decoded

  if (channel == ch::kPose) {
    pose_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    const PoseViews v =
        pose_views(&pose_track_, m.utime, m.position_ned, m.roll, m.pitch, m.yaw, m.position_covariance, "base_link");
    emit("POSE", m.utime, [&] {
      return json{{"timestamp", stamp(m.utime)}, {"utime", m.utime}, {"north_m", m.position_ned[0]},
                  {"east_m", m.position_ned[1]}, {"down_m", m.position_ned[2]}, {"velocity_n", m.velocity_ned[0]},
                  {"velocity_e", m.velocity_ned[1]}, {"velocity_d", m.velocity_ned[2]}, {"roll_deg", m.roll * kDeg},
                  {"pitch_deg", m.pitch * kDeg}, {"yaw_deg", m.yaw * kDeg}, {"height_agl_m", m.height_agl_m},
                  {"sigma_north_m", sigma(m.position_covariance[0][0])},
                  {"sigma_east_m", sigma(m.position_covariance[1][1])},
                  {"sigma_down_m", sigma(m.position_covariance[2][2])},
                  {"sigma_yaw_deg", sigma(m.yaw_variance) * kDeg},
                  {"protection_level_m", m.horizontal_protection_level_m}, {"flags", m.flags},
                  {"flag_vo_gap", bit(m.flags, pose_t::FLAG_VO_GAP)},
                  {"flag_ins_yaw_rejected", bit(m.flags, pose_t::FLAG_INS_YAW_REJECTED)},
                  {"flag_no_altimeter", bit(m.flags, pose_t::FLAG_NO_ALTIMETER)},
                  {"flag_initializing", bit(m.flags, pose_t::FLAG_INITIALIZING)},
                  {"flag_coasting", bit(m.flags, pose_t::FLAG_COASTING)}, {"frames", m.frames}};
    });
    if (origin_known_) emit("POSE/fix", m.utime, [&] { return v.fix; });
    emit("POSE/pose", m.utime, [&] { return v.pose; });
    emit("POSE/tf", m.utime, [&] { return v.tf; });
    // The level frame of the same point: heading only, the frame VO_GROUND's points are in.
    emit("POSE/level_tf", m.utime, [&] {
      json level = v.tf;
      level["child_frame_id"] = "base_link_level";
      level["rotation"] = quat(enu_flu_orientation(0.0, 0.0, m.yaw));
      return level;
    });
  } else if (channel == ch::kGroundTruth) {
    ground_truth_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    double ned[3];
    for (int k = 0; k < 3; ++k) ned[k] = m.position_ned[k] - truth_offset_ned_[k];
    const PoseViews v = pose_views(&truth_track_, m.utime, ned, m.roll, m.pitch, m.yaw, nullptr, "truth_base_link");
    emit("GROUND_TRUTH", m.utime, [&] {
      return json{{"timestamp", stamp(m.utime)}, {"utime", m.utime}, {"kind", m.kind},
                  {"north_m", m.position_ned[0]}, {"east_m", m.position_ned[1]}, {"down_m", m.position_ned[2]},
                  {"velocity_n", m.velocity_ned[0]}, {"velocity_e", m.velocity_ned[1]},
                  {"velocity_d", m.velocity_ned[2]}, {"roll_deg", m.roll * kDeg}, {"pitch_deg", m.pitch * kDeg},
                  {"yaw_deg", m.yaw * kDeg}, {"height_agl_m", m.height_agl_m},
                  {"terrain_height_m", m.terrain_height_m}};
    });
    if (truth_origin_known_) {
      if (origin_known_) emit("GROUND_TRUTH/fix", m.utime, [&] { return v.fix; });
      emit("GROUND_TRUTH/pose", m.utime, [&] { return v.pose; });
      emit("GROUND_TRUTH/tf", m.utime, [&] { return v.tf; });
    }
  } else if (channel == ch::kCameraImage) {
    image_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    if (options_.image_rate_hz > 0) {
      // The first frame of each 1/rate slot of sensor time: the configured
      // rate on average whatever the camera's rate.
      const int64_t bucket = static_cast<int64_t>(std::floor(m.utime * 1e-6 * options_.image_rate_hz));
      if (bucket == last_image_bucket_) {
        ++images_decimated_;
        return true;
      }
      last_image_bucket_ = bucket;
    }
    emit("CAMERA_IMAGE", m.utime, [&] {
      const bool mono16 = m.pixel_format == image_t::PIXEL_MONO16;
      return json{{"timestamp", stamp(m.utime)}, {"frame_id", "camera"}, {"width", m.width},
                  {"height", m.height}, {"encoding", mono16 ? "mono16" : "mono8"}, {"step", m.stride},
                  {"data", base64(m.data.data(), m.data.size())}};
    });
  } else if (channel == ch::kTracks) {
    tracks_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    emit("TRACKS", m.utime, [&] {
      // Flow vectors (previous -> current pixel) as one line list, current
      // positions as points; colour by age would need per-point colours for
      // both, so one colour each keeps the message small.
      json lines = json::array(), points = json::array();
      for (int i = 0; i < m.num_tracks; ++i) {
        lines.push_back({{"x", m.prev_px[i][0]}, {"y", m.prev_px[i][1]}});
        lines.push_back({{"x", m.curr_px[i][0]}, {"y", m.curr_px[i][1]}});
        points.push_back({{"x", m.curr_px[i][0]}, {"y", m.curr_px[i][1]}});
      }
      auto annotation = [&](int type, json pts, json colour, double thickness) {
        return json{{"timestamp", stamp(m.utime)}, {"type", type}, {"points", std::move(pts)},
                    {"outline_color", colour}, {"outline_colors", json::array()},
                    {"fill_color", rgba(0, 0, 0, 0)}, {"thickness", thickness}};
      };
      return json{{"timestamp", stamp(m.utime)},
                  {"circles", json::array()},
                  {"points", json::array({annotation(4, lines, rgba(1.0, 0.8, 0.0, 1.0), 1.5),
                                          annotation(1, points, rgba(0.1, 1.0, 0.3, 1.0), 4.0)})},
                  {"texts", json::array()}};
    });
    emit("TRACKS/stats", m.utime, [&] {
      double age = 0, flow = 0;
      for (int i = 0; i < m.num_tracks; ++i) {
        age += m.age[i];
        flow += std::hypot(m.curr_px[i][0] - m.prev_px[i][0], m.curr_px[i][1] - m.prev_px[i][1]);
      }
      const double n = std::max(1, m.num_tracks);
      return json{{"timestamp", stamp(m.utime)}, {"utime", m.utime}, {"prev_utime", m.prev_utime},
                  {"frame_counter", m.frame_counter}, {"flags", m.flags}, {"num_tracks", m.num_tracks},
                  {"mean_age", age / n}, {"mean_flow_px", flow / n}};
    });
  } else if (channel == ch::kVoDelta) {
    vo_delta_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    emit("VO_DELTA", m.utime, [&] {
      return json{{"timestamp", stamp(m.utime)}, {"utime", m.utime}, {"prev_utime", m.prev_utime}, {"dx", m.dx},
                  {"dy", m.dy}, {"dz", m.dz}, {"dyaw_deg", m.dyaw * kDeg}, {"ground_roll_deg", m.ground_roll * kDeg},
                  {"ground_pitch_deg", m.ground_pitch * kDeg}, {"sigma_dx", sigma(m.covariance[0][0])},
                  {"sigma_dy", sigma(m.covariance[1][1])}, {"sigma_dz", sigma(m.covariance[2][2])},
                  {"sigma_dyaw_deg", sigma(m.covariance[3][3]) * kDeg}, {"altitude_m", m.altitude_m},
                  {"inliers", m.inliers}, {"outliers", m.outliers}, {"residual_rms_px", m.residual_rms_px},
                  {"iterations", m.iterations}, {"quality", m.quality},
                  {"quality_too_few_features", bit(m.quality, vo_delta_t::QUALITY_TOO_FEW_FEATURES)},
                  {"quality_no_altimeter", bit(m.quality, vo_delta_t::QUALITY_NO_ALTIMETER)},
                  {"quality_stale_altimeter", bit(m.quality, vo_delta_t::QUALITY_STALE_ALTIMETER)},
                  {"quality_not_converged", bit(m.quality, vo_delta_t::QUALITY_NOT_CONVERGED)},
                  {"quality_no_attitude", bit(m.quality, vo_delta_t::QUALITY_NO_ATTITUDE)},
                  {"quality_frame_gap", bit(m.quality, vo_delta_t::QUALITY_FRAME_GAP)},
                  {"quality_high_residual", bit(m.quality, vo_delta_t::QUALITY_HIGH_RESIDUAL)},
                  {"quality_depth_layers", bit(m.quality, vo_delta_t::QUALITY_DEPTH_LAYERS)},
                  {"quality_heading_contradicts", bit(m.quality, vo_delta_t::QUALITY_HEADING_CONTRADICTS)},
                  {"variant", m.variant}};
    });
  } else if (channel == ch::kVoGround) {
    ground_points_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    emit("VO_GROUND", m.utime, [&] { return ground_point_cloud(m); });
  } else if (channel == ch::kStatus) {
    status_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    emit("STATUS", m.utime, [&] {
      json counters = json::object();
      for (int i = 0; i < m.num_counters; ++i) counters[m.counter_names[i]] = m.counter_values[i];
      return json{{"timestamp", stamp(m.utime)}, {"utime", m.utime}, {"name", m.name}, {"pid", m.pid},
                  {"state", m.state}, {"state_name", state_name(m.state)}, {"detail", m.detail},
                  {"received", m.received}, {"published", m.published}, {"dropped", m.dropped},
                  {"errors", m.errors}, {"malformed", m.malformed}, {"latency_p50_ms", m.latency_p50_ms},
                  {"latency_p99_ms", m.latency_p99_ms}, {"latency_max_ms", m.latency_max_ms},
                  {"counters", counters}};
    });
  } else if (channel == ch::kIns) {
    ins_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    emit("INS", m.utime, [&] {
      return json{{"timestamp", stamp(m.utime)}, {"utime", m.utime}, {"device_utime", m.device_utime},
                  {"roll_deg", m.roll * kDeg}, {"pitch_deg", m.pitch * kDeg}, {"yaw_deg", m.yaw * kDeg},
                  {"latitude_deg", m.latitude_deg}, {"longitude_deg", m.longitude_deg}, {"height_m", m.height_m},
                  {"velocity_n", m.velocity_ned[0]}, {"velocity_e", m.velocity_ned[1]},
                  {"velocity_d", m.velocity_ned[2]}, {"ins_status", m.ins_status}, {"flags", m.flags}};
    });
  } else if (channel == ch::kAltimeter) {
    altimeter_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    emit("ALTIMETER", m.utime, [&] {
      return json{{"timestamp", stamp(m.utime)}, {"utime", m.utime}, {"range_m", m.range_m},
                  {"beam_x", m.beam_body[0]}, {"beam_y", m.beam_body[1]}, {"beam_z", m.beam_body[2]},
                  {"signal_quality", m.signal_quality}, {"validity", m.validity}};
    });
  } else if (channel == ch::kCameraTrigger) {
    trigger_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    emit("CAMERA_TRIGGER", m.utime, [&] {
      return json{{"timestamp", stamp(m.utime)}, {"utime", m.utime}, {"device_utime", m.device_utime},
                  {"sequence", m.sequence}, {"edge", m.edge}, {"flags", m.flags}};
    });
  } else if (channel == ch::kConfig) {
    config_t m;
    if (!decode_message(data, size, &m, reason)) return false;
    emit("CONFIG", m.utime, [&] {
      return json{{"timestamp", stamp(m.utime)}, {"utime", m.utime}, {"name", m.name}, {"source", m.source},
                  {"yaml", m.yaml}};
    });
  }
  return true;
}

}  // namespace nadir
