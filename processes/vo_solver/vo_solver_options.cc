#include "processes/vo_solver/vo_solver_options.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "common/camera_model.h"

namespace nadir {

namespace {
int64_t ms_to_us(double ms) { return static_cast<int64_t>(ms * 1000.0 + (ms >= 0 ? 0.5 : -0.5)); }
}  // namespace

VoSolverOptions VoSolverOptions::from_config(const Config& root) {
  VoSolverOptions o;
  const CameraModel camera = CameraModel::from_config(root);
  o.body_from_camera = camera.body_from_camera;
  o.solver.focal_px = camera.fx;

  const Config altimeter = root.section_or_empty("altimeter");
  const auto beam = altimeter.get<std::vector<double>>("beam_body", std::vector<double>{0, 0, 1});
  if (beam.size() != 3) throw altimeter.error("beam_body", "must list x, y, z in the body frame");
  o.default_beam_body = Eigen::Vector3d(beam[0], beam[1], beam[2]);
  if (!(o.default_beam_body.norm() > 0.5 && o.default_beam_body.norm() < 2.0)) {
    throw altimeter.error("beam_body", "must be a unit vector");
  }
  o.default_beam_body.normalize();

  const Config c = root.section_or_empty("vo_solver");
  const std::string variant = c.get<std::string>("variant", "paper");
  try {
    o.solver.variant = vo::variant_from_name(variant);
  } catch (const std::invalid_argument& e) {
    throw c.error("variant", "= '" + variant + "' is not one of paper, level_ground, homography, flow, feature_depth");
  }
  auto& s = o.solver;
  s.threshold_focal_px = c.get_in_range("threshold_focal_px", s.threshold_focal_px, 1.0, 1e5);
  s.min_features = c.get_in_range("min_features", s.min_features, 5, 10000);
  s.max_robust_iterations = c.get_in_range("max_robust_iterations", s.max_robust_iterations, 1, 100);
  s.max_lm_iterations = c.get_in_range("max_lm_iterations", s.max_lm_iterations, 1, 100);
  s.min_threshold_px = c.get_in_range("min_threshold_px", s.min_threshold_px, 0.01, 100.0);
  s.threshold_mad_scale = c.get_in_range("threshold_mad_scale", s.threshold_mad_scale, 1.0, 20.0);
  s.max_threshold_px = c.get_in_range("max_threshold_px", s.max_threshold_px, 0.01, 1000.0);
  s.layers.min_fraction = c.get_in_range("layer_min_fraction", s.layers.min_fraction, 0.01, 0.5);
  s.layers.min_separation = c.get_in_range("layer_min_separation", s.layers.min_separation, 0.0, 10.0);
  s.layers.min_separation_sigma =
      c.get_in_range("layer_min_separation_sigma", s.layers.min_separation_sigma, 3.0, 100.0);
  s.convergence_tolerance = c.get_in_range("convergence_tolerance", s.convergence_tolerance, 1e-15, 1e-2);
  s.convergence_sigma_fraction =
      c.get_in_range("convergence_sigma_fraction", s.convergence_sigma_fraction, 0.0, 0.5);
  s.max_residual_rms_px = c.get_in_range("max_residual_rms_px", s.max_residual_rms_px, 0.01, 100.0);
  s.min_inlier_fraction = c.get_in_range("min_inlier_fraction", s.min_inlier_fraction, 0.0, 1.0);
  s.homography_ransac_px = c.get_in_range("homography_ransac_px", s.homography_ransac_px, 0.01, 100.0);
  const Config d = c.section_or_empty("feature_depth");
  auto& fd = s.feature_depth;
  fd.max_relative_sigma = d.get_in_range("max_relative_sigma", fd.max_relative_sigma, 1e-6, 1.0);
  fd.min_own_depth_features = d.get_in_range("min_own_depth_features", fd.min_own_depth_features, 5, 10000);
  fd.anchor_radius = d.get_in_range("anchor_radius", fd.anchor_radius, 1e-3, 2.0);
  fd.min_anchor_features = d.get_in_range("min_anchor_features", fd.min_anchor_features, 3, 10000);
  fd.scale_carry_pairs = d.get_in_range("scale_carry_pairs", fd.scale_carry_pairs, 0, 1000);
  fd.scale_filter = d.get<bool>("scale_filter", fd.scale_filter);
  fd.scale_process_noise = d.get_in_range("scale_process_noise", fd.scale_process_noise, 1e-6, 1.0);
  fd.patch_feature_weight = d.get_in_range("patch_feature_weight", fd.patch_feature_weight, 0.0, 1.0);
  fd.triangulation_noise_px = d.get_in_range("triangulation_noise_px", fd.triangulation_noise_px, 1e-3, 100.0);
  fd.min_parallax_rad = d.get_in_range("min_parallax_rad", fd.min_parallax_rad, 1e-6, 0.5);
  fd.relative_process_noise = d.get_in_range("relative_process_noise", fd.relative_process_noise, 0.0, 1.0);
  fd.max_epipolar_px = d.get_in_range("max_epipolar_px", fd.max_epipolar_px, 1e-3, 100.0);
  fd.max_depth_jump_sigma = d.get_in_range("max_depth_jump_sigma", fd.max_depth_jump_sigma, 1.0, 100.0);
  fd.range_from_sample_position = d.get<bool>("range_from_sample_position", fd.range_from_sample_position);
  fd.ins_tilt_sigma_deg = d.get_in_range("ins_tilt_sigma_deg", fd.ins_tilt_sigma_deg, 0.0, 5.0);
  const std::string anchor_surface = d.get<std::string>(
      "anchor_surface", fd.anchor_surface == vo::AnchorSurfaceModel::kQuadratic ? "quadratic" : "plane");
  if (anchor_surface != "quadratic" && anchor_surface != "plane") {
    throw d.error("anchor_surface", "= '" + anchor_surface + "' must be quadratic or plane");
  }
  fd.anchor_surface =
      anchor_surface == "quadratic" ? vo::AnchorSurfaceModel::kQuadratic : vo::AnchorSurfaceModel::kPlane;
  const std::string anchor_spots =
      d.get<std::string>("anchor_spots", fd.anchor_spots == vo::AnchorSpots::kTrack ? "track" : "beam");
  if (anchor_spots != "beam" && anchor_spots != "track") {
    throw d.error("anchor_spots", "= '" + anchor_spots + "' must be beam or track");
  }
  fd.anchor_spots = anchor_spots == "track" ? vo::AnchorSpots::kTrack : vo::AnchorSpots::kBeam;
  const std::string dz_mode = c.get<std::string>("dz_mode", "symmetric");
  if (dz_mode != "symmetric" && dz_mode != "forward") {
    throw c.error("dz_mode", "= '" + dz_mode + "' must be symmetric or forward");
  }
  s.symmetric_dz = dz_mode == "symmetric";
  const std::string dyaw_start = c.get<std::string>("dyaw_start", "ins");
  if (dyaw_start != "ins" && dyaw_start != "zero") {
    throw c.error("dyaw_start", "= '" + dyaw_start + "' must be ins or zero");
  }
  s.dyaw_start_from_ins = dyaw_start == "ins";

  o.uncertainty = vo::UncertaintyOptions::from_config(c);

  const Config y = c.section_or_empty("sync");
  auto& t = o.sync;
  const std::string attitude_policy = y.get<std::string>("attitude_policy", "interpolate");
  try {
    t.attitude_policy = attitude_policy_from_name(attitude_policy);
  } catch (const std::invalid_argument& e) {
    throw y.error("attitude_policy", "= '" + attitude_policy + "' must be propagate or interpolate");
  }
  t.ins_min_interval_us = ms_to_us(y.get_in_range("ins_min_interval_ms", 9.0, 0.0, 1000.0));
  t.max_ins_gap_us = ms_to_us(y.get_in_range("max_ins_gap_ms", 100.0, 0.001, 10000.0));
  t.max_ins_extrapolation_us = ms_to_us(y.get_in_range("max_ins_extrapolation_ms", 20.0, 0.0, 1000.0));
  t.altimeter_staleness_us = ms_to_us(y.get_in_range("altimeter_staleness_ms", 200.0, 0.001, 60000.0));
  t.altimeter_wait_us = ms_to_us(y.get_in_range("altimeter_wait_ms", 300.0, 0.0, 10000.0));
  t.settle_us = ms_to_us(y.get_in_range("settle_ms", 0.0, 0.0, 10000.0));
  const std::string altimeter_mode = y.get<std::string>("altimeter_mode", "latest");
  if (altimeter_mode != "latest" && altimeter_mode != "interpolate") {
    throw y.error("altimeter_mode", "= '" + altimeter_mode + "' must be latest or interpolate");
  }
  t.altimeter_interpolate = altimeter_mode == "interpolate";
  t.max_frame_interval_us = ms_to_us(y.get_in_range("max_frame_interval_ms", 250.0, 0.001, 3600000.0));
  t.max_pending_frames = y.get_in_range("max_pending_frames", t.max_pending_frames, 1, 10000);
  t.max_ins_samples = y.get_in_range("max_ins_samples", t.max_ins_samples, 2, 1000000);
  t.max_altimeter_samples = y.get_in_range("max_altimeter_samples", t.max_altimeter_samples, 2, 1000000);
  t.calibration = SensorCalibration::from_config(root);
  try {
    o.solver.Check();
    o.sync.Check();
  } catch (const std::invalid_argument& e) {
    throw c.error("", e.what());
  }
  return o;
}

}  // namespace nadir
