#include "tools/eval/trajectory_metrics.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "common/geometry.h"
#include "common/json_writer.h"
#include "common/status.h"
#include "common/time_base.h"
#include "tools/eval/consistency.h"
#include "tools/eval/truth_lookup.h"

namespace nadir {

namespace {

// The reject mask yaw fusion ran with (its CONFIG, in the estimator's), else its default.
int32_t reject_quality_mask(const EvalData& data) {
  if (data.estimator_config_yaml.empty()) return kUnsolvedQualityMask;
  try {
    const Config root = Config::parse(data.estimator_config_yaml, "CONFIG of " + data.estimator_config_name);
    return root.section_or_empty("yaw_fusion").get<int32_t>("reject_quality_mask", kUnsolvedQualityMask);
  } catch (const ConfigError&) {
    return kUnsolvedQualityMask;
  }
}

}  // namespace

EvalResult evaluate(const EvalData& data) {
  EvalResult result;
  EvalMetrics& m = result.metrics;
  const pose_t* first = nullptr;
  TruthAt truth0{};
  TruthAt previous{};
  double distance = 0;
  double sum_v2 = 0, sum_yaw2 = 0, sum_e2_h = 0, sum_e2_v = 0;
  int64_t velocity_samples = 0;
  std::vector<float> latencies;
  NeesSummary nees_h(kChi2Dof2Pct95), nees_yaw(kChi2Dof1Pct95);
  ProtectionLevelSummary protection;
  for (size_t i = 0; i < data.poses.size(); ++i) {
    const pose_t& p = data.poses[i];
    TruthAt t{};
    if (!truth_at(data.truth, p.utime, &t)) continue;
    if (first == nullptr) {
      first = &p;
      truth0 = t;
      previous = t;
    }
    EvalSample s;
    s.t_s = us_to_s(p.utime - first->utime);
    double step2 = 0;
    for (int k = 0; k < 3; ++k) {
      s.estimate[k] = p.position_ned[k] - first->position_ned[k];
      s.truth[k] = t.position[k] - truth0.position[k];
      step2 += (t.position[k] - previous.position[k]) * (t.position[k] - previous.position[k]);
      s.velocity_error[k] = p.velocity_ned[k] - t.velocity[k];
    }
    distance += std::sqrt(step2);
    previous = t;
    s.distance_m = distance;
    s.error_h_m = std::hypot(s.estimate[0] - s.truth[0], s.estimate[1] - s.truth[1]);
    s.error_v_m = s.estimate[2] - s.truth[2];
    s.yaw_error_deg = rad_to_deg(angle_difference(p.yaw, t.yaw));
    s.flags = p.flags;
    s.sigma_h_m = std::sqrt(std::max(0.0, p.position_covariance[0][0] + p.position_covariance[1][1]));
    s.sigma_n_m = std::sqrt(std::max(0.0, p.position_covariance[0][0]));
    s.sigma_e_m = std::sqrt(std::max(0.0, p.position_covariance[1][1]));
    s.sigma_d_m = std::sqrt(std::max(0.0, p.position_covariance[2][2]));
    s.cov_ne_m2 = 0.5 * (p.position_covariance[0][1] + p.position_covariance[1][0]);
    s.sigma_yaw_deg = rad_to_deg(std::sqrt(std::max(0.0, p.yaw_variance)));
    // The first pose is the origin (error and covariance zero): no statement.
    if (&p != first) {
      s.nees_h = horizontal_nees(s.estimate[0] - s.truth[0], s.estimate[1] - s.truth[1], p.position_covariance[0][0],
                                 s.cov_ne_m2, p.position_covariance[1][1]);
      s.nees_yaw = scalar_nees(deg_to_rad(s.yaw_error_deg), p.yaw_variance);
      nees_h.add(s.nees_h);
      nees_yaw.add(s.nees_yaw);
      protection.add(s.error_h_m, p.horizontal_protection_level_m);
    }
    s.protection_level_m = p.horizontal_protection_level_m;
    // The origin's velocity is not an estimate yet (no pair before it).
    if (&p != first) {
      const double v_h = std::hypot(s.velocity_error[0], s.velocity_error[1]);
      sum_v2 += v_h * v_h;
      ++velocity_samples;
      m.max_velocity_error_h = std::max(m.max_velocity_error_h, v_h);
    }
    sum_yaw2 += s.yaw_error_deg * s.yaw_error_deg;
    m.max_error_h_m = std::max(m.max_error_h_m, s.error_h_m);
    sum_e2_h += s.error_h_m * s.error_h_m;
    sum_e2_v += s.error_v_m * s.error_v_m;
    if (p.flags != 0) ++m.poses_flagged;
    latencies.push_back(static_cast<float>(us_to_s(data.pose_log_timestamps[i] - p.utime) * 1e3));
    result.samples.push_back(s);
  }
  if (result.samples.size() < 2) {
    throw std::runtime_error("POSE and GROUND_TRUTH do not overlap in sensor time (" +
                             std::to_string(result.samples.size()) + " aligned poses)");
  }
  std::vector<float> errors_h;
  for (const EvalSample& s : result.samples) errors_h.push_back(static_cast<float>(s.error_h_m));
  m.p95_error_h_m = percentile(errors_h, 95);
  m.coasts = coast_episodes(result.samples, pose_t::FLAG_COASTING);
  for (const CoastEpisode& c : m.coasts) m.coast_s += c.duration_s;
  m.map_fixes = map_fix_metrics(data.map_fixes, data.poses, data.truth, *first, truth0);
  const EvalSample& last = result.samples.back();
  const double n = static_cast<double>(result.samples.size());
  m.poses = static_cast<int64_t>(result.samples.size());
  m.duration_s = last.t_s;
  m.distance_m = last.distance_m;
  m.final_error_h_m = last.error_h_m;
  m.final_error_v_m = last.error_v_m;
  m.final_error_3d_m = std::hypot(last.error_h_m, last.error_v_m);
  if (m.distance_m > 0) {
    m.error_pct_h = 100.0 * m.final_error_h_m / m.distance_m;
    m.error_pct_v = 100.0 * std::fabs(m.final_error_v_m) / m.distance_m;
    m.error_pct_3d = 100.0 * m.final_error_3d_m / m.distance_m;
  }
  m.rms_velocity_error_h = std::sqrt(sum_v2 / static_cast<double>(std::max<int64_t>(1, velocity_samples)));
  m.rms_error_h_m = std::sqrt(sum_e2_h / n);
  m.rms_error_3d_m = std::sqrt((sum_e2_h + sum_e2_v) / n);
  if (m.distance_m > 0) m.rms_error_pct_3d = 100.0 * m.rms_error_3d_m / m.distance_m;
  m.rms_yaw_error_deg = std::sqrt(sum_yaw2 / n);
  m.images = data.pipeline.frames;
  m.triggers = data.triggers;
  m.frames_dropped = std::max<int64_t>(0, data.triggers - m.images);
  m.records_not_pipeline =
      data.pipeline.other_images + data.pipeline.other_tracks + data.pipeline.other_vo_deltas;
  m.capture_corrupt_records = data.corrupt_records;
  m.capture_truncated = data.truncated;
  m.capture_holes = static_cast<int64_t>(data.holes.size());
  for (const LogHole& h : data.holes) m.capture_hole_seconds = std::max(m.capture_hole_seconds, h.seconds());
  m.nees_samples = nees_h.samples();
  m.nees_h_mean = nees_h.mean();
  m.nees_h_within_95_pct = nees_h.within_95_pct();
  m.nees_yaw_mean = nees_yaw.mean();
  m.nees_yaw_within_95_pct = nees_yaw.within_95_pct();
  m.pl_exceeded_pct = protection.exceeded_pct();
  m.pl_samples = protection.samples();
  m.pl_unavailable = protection.unavailable();
  m.capture_missing = data.accounting.missing_total();
  for (const ChannelAccount& c : data.accounting.channels) m.capture_unaccounted += c.unaccounted();
  m.udp_rx_drops = data.accounting.udp_rx_drops;
  for (const auto& [name, s] : data.last_status) {
    m.process_counts[name] = {s.received, s.published, s.dropped, s.errors, s.malformed};
  }
  m.tracks = data.pipeline.tracks;
  m.vo_deltas = data.pipeline.vo_deltas;
  m.vo_deltas_flagged = data.pipeline.vo_deltas_flagged;
  std::unique_ptr<CameraModel> camera;
  if (data.estimator_config_yaml.empty()) {
    m.footprint_problem = "no CONFIG from vo_solver or tracker in the log";
  } else {
    try {
      camera = std::make_unique<CameraModel>(CameraModel::from_config(
          Config::parse(data.estimator_config_yaml, "CONFIG of " + data.estimator_config_name)));
    } catch (const ConfigError& e) {
      m.footprint_problem = e.what();
    }
  }
  result.pairs = evaluate_pairs(data.deltas, data.truth, camera.get(), reject_quality_mask(data));
  if (result.pairs.footprints) {
    m.pairs_apart = result.pairs.apart;
    m.pairs_overlapping_solved_pct = result.pairs.overlapping_solved_pct;
  }
  m.pairs = result.pairs.pairs;
  m.pairs_solved = result.pairs.solved;
  m.pairs_solved_pct = result.pairs.solved_pct;
  m.pairs_not_solved_flagged = result.pairs.pairs - result.pairs.solved;
  for (int bit = 0; bit < kVoQualityBits; ++bit) {
    if ((1 << bit) == vo_delta_t::QUALITY_HEADING_CONTRADICTS) {
      m.pairs_heading_contradicts = result.pairs.not_solved_by_bit[bit];
    }
  }
  m.pairs_not_solved_why = format_not_solved(result.pairs);
  m.pair_error_pct_median = result.pairs.error_pct_median;
  m.pair_error_pct_p90 = result.pairs.error_pct_p90;
  m.pair_step_median_m = result.pairs.step_median_m;
  m.imported = data.imported;
  m.latency_measured = !data.imported && !data.lockstep_replay;
  m.latency_p50_ms = percentile(latencies, 50);
  m.latency_p99_ms = percentile(latencies, 99);
  m.latency_max_ms = percentile(latencies, 100);
  m.after_image_latency_p50_ms = percentile(data.after_image_latency_ms, 50);
  m.after_image_latency_p99_ms = percentile(data.after_image_latency_ms, 99);
  m.after_image_latency_max_ms = percentile(data.after_image_latency_ms, 100);

  // Geographic reference: the INS fix nearest the first pose, moved back by
  // the truth offset between them.
  if (!data.ins.empty()) {
    const auto nearest = std::min_element(data.ins.begin(), data.ins.end(), [&](const ins_t& a, const ins_t& b) {
      return std::llabs(a.utime - first->utime) < std::llabs(b.utime - first->utime);
    });
    result.reference_lat_deg = nearest->latitude_deg;
    result.reference_lon_deg = nearest->longitude_deg;
    result.has_reference = nearest->latitude_deg != 0.0 || nearest->longitude_deg != 0.0;
  }
  return result;
}

std::string metrics_json(const EvalMetrics& m) {
  JsonWriter j;
  j.begin_object();
  j.field("duration_s", m.duration_s).field("distance_m", m.distance_m);
  j.field("final_error_h_m", m.final_error_h_m).field("final_error_v_m", m.final_error_v_m);
  j.field("final_error_3d_m", m.final_error_3d_m).field("error_pct_h", m.error_pct_h);
  j.field("error_pct_v", m.error_pct_v).field("error_pct_3d", m.error_pct_3d);
  j.field("rms_error_h_m", m.rms_error_h_m).field("rms_error_3d_m", m.rms_error_3d_m);
  j.field("rms_error_pct_3d", m.rms_error_pct_3d);
  j.field("max_error_h_m", m.max_error_h_m).field("p95_error_h_m", m.p95_error_h_m);
  j.field("rms_velocity_error_h", m.rms_velocity_error_h);
  const MapFixMetrics& f = m.map_fixes;
  j.key("map_fixes").begin_object();
  j.field("fixes", f.fixes).field("applied", f.applied).field("rejected", f.rejected);
  j.field("error_median_m", f.error_median_m).field("error_p95_m", f.error_p95_m).field("error_max_m", f.error_max_m);
  j.field("sigma_median_m", f.sigma_median_m).field("mahalanobis_max", f.mahalanobis_max);
  j.field("beyond_3_sigma", f.beyond_3_sigma);
  j.end_object();
  j.field("max_velocity_error_h", m.max_velocity_error_h).field("rms_yaw_error_deg", m.rms_yaw_error_deg);
  j.field("poses", m.poses).field("poses_flagged", m.poses_flagged).field("images", m.images);
  j.field("coast_s", m.coast_s);
  j.key("coasts").begin_array();
  for (const CoastEpisode& c : m.coasts) {
    j.begin_object().field("start_s", c.start_s).field("duration_s", c.duration_s);
    j.field("added_h_m", c.added_h_m).field("added_v_m", c.added_v_m);
    j.field("error_h_m", c.error_h_m).field("sigma_h_m", c.sigma_h_m).end_object();
  }
  j.end_array();
  j.field("triggers", m.triggers).field("frames_dropped", m.frames_dropped).field("tracks", m.tracks);
  j.field("capture_corrupt_records", m.capture_corrupt_records).field("capture_truncated", m.capture_truncated);
  j.field("capture_holes", m.capture_holes).field("capture_longest_hole_s", m.capture_hole_seconds);
  j.field("nees_samples", m.nees_samples).field("nees_h_mean", m.nees_h_mean);
  j.field("nees_h_within_95_pct", m.nees_h_within_95_pct).field("nees_yaw_mean", m.nees_yaw_mean);
  j.field("nees_yaw_within_95_pct", m.nees_yaw_within_95_pct);
  j.field("pl_exceeded_pct", m.pl_exceeded_pct).field("pl_samples", m.pl_samples);
  j.field("pl_unavailable", m.pl_unavailable);
  j.field("capture_missing", m.capture_missing).field("capture_unaccounted", m.capture_unaccounted);
  j.key("processes").begin_object();
  for (const auto& [name, c] : m.process_counts) {
    j.key(name).begin_object().field("received", c[0]).field("published", c[1]).field("dropped", c[2]);
    j.field("errors", c[3]).field("malformed", c[4]);
    const auto drops = m.udp_rx_drops.find(name);
    j.field("udp_rx_drops", drops == m.udp_rx_drops.end() ? int64_t{0} : drops->second).end_object();
  }
  j.end_object();
  j.field("vo_deltas", m.vo_deltas).field("vo_deltas_flagged", m.vo_deltas_flagged);
  j.field("records_not_pipeline", m.records_not_pipeline);
  j.field("pairs", m.pairs).field("pairs_solved", m.pairs_solved).field("pairs_solved_pct", m.pairs_solved_pct);
  j.field("pair_error_pct_median", m.pair_error_pct_median).field("pair_error_pct_p90", m.pair_error_pct_p90);
  j.field("pair_step_median_m", m.pair_step_median_m);
  j.field("pairs_not_solved_flagged", m.pairs_not_solved_flagged);
  j.field("pairs_heading_contradicts", m.pairs_heading_contradicts);
  j.field("pairs_not_solved_why", m.pairs_not_solved_why).field("imported", m.imported);
  j.field("latency_measured", m.latency_measured);
  j.field("pairs_apart", m.pairs_apart).field("pairs_overlapping_solved_pct", m.pairs_overlapping_solved_pct);
  j.field("latency_p50_ms", m.latency_p50_ms).field("latency_p99_ms", m.latency_p99_ms);
  j.field("latency_max_ms", m.latency_max_ms);
  j.field("after_image_latency_p50_ms", m.after_image_latency_p50_ms);
  j.field("after_image_latency_p99_ms", m.after_image_latency_p99_ms);
  j.field("after_image_latency_max_ms", m.after_image_latency_max_ms);
  j.end_object();
  return j.str();
}

}  // namespace nadir
