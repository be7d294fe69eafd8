#include "processes/vo_solver/vo_solver_options.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/camera_model.h"

namespace nadir {

const OptionsSchema<VoSolverOptions>& VoSolverOptions::schema() {
  using O = VoSolverOptions;
  using S = vo::SolverOptions;
  using D = vo::FeatureDepthOptions;
  using L = vo::DepthLayerOptions;
  using Y = vo::SyncOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("vo_solver", "Frame-pair solver (paper Algorithm 1 and its variants), its input "
                                    "synchronization and the sensor uncertainty put on VO_DELTA.");
    s.choice<vo::Variant>("variant",
                          {{"paper", vo::Variant::kPaper},
                           {"level_ground", vo::Variant::kLevelGround},
                           {"homography", vo::Variant::kHomography},
                           {"flow", vo::Variant::kFlow},
                           {"feature_depth", vo::Variant::kFeatureDepth}},
                          "solver model", &O::solver, &S::variant)
        .number("min_features", 5, 10000, "", "fewer (before or after the robust fit): QUALITY_TOO_FEW_FEATURES",
                &O::solver, &S::min_features)
        .number("max_robust_iterations", 1, 100, "", "reweighting iterations (Algorithm 1 lines 7-20)", &O::solver,
                &S::max_robust_iterations)
        .number("max_lm_iterations", 1, 100, "", "Levenberg-Marquardt steps per reweighting (lines 9-16)",
                &O::solver, &S::max_lm_iterations)
        .number("threshold_focal_px", 1.0, 1e5, "px",
                "the *_px keys are pixels at this focal length (scaled by fx / this, never down)", &O::solver,
                &S::threshold_focal_px)
        .number("min_threshold_px", 0.01, 100.0, "px", "outlier cut on the image reprojection error, at least",
                &O::solver, &S::min_threshold_px)
        .number("threshold_mad_scale", 1.0, 20.0, "", "... or this many robust sigmas of the errors, if larger",
                &O::solver, &S::threshold_mad_scale)
        .number("max_threshold_px", 0.01, 1000.0, "px", "... but never above this (from the second reweighting on)",
                &O::solver, &S::max_threshold_px)
        .number("layer_min_fraction", 0.01, 0.5, "", "QUALITY_DEPTH_LAYERS: each depth group holds this share at least",
                &O::solver, &S::layers, &L::min_fraction)
        .number("layer_min_separation", 0.0, 10.0, "", "... their mean relative depths differ by this at least",
                &O::solver, &S::layers, &L::min_separation)
        .number("layer_min_separation_sigma", 3.0, 100.0, "",
                "... and by this many pooled within-group standard deviations", &O::solver, &S::layers,
                &L::min_separation_sigma)
        .number("convergence_tolerance", 1e-15, 1e-2, "", "parameter change (translation / height, rad) to stop",
                &O::solver, &S::convergence_tolerance)
        .number("convergence_sigma_fraction", 0.0, 0.5, "",
                "... or every unknown moved less than this share of its sigma (0: off)", &O::solver,
                &S::convergence_sigma_fraction)
        .number("max_residual_rms_px", 0.01, 100.0, "px", "inlier RMS above: QUALITY_HIGH_RESIDUAL", &O::solver,
                &S::max_residual_rms_px)
        .number("min_inlier_fraction", 0.0, 1.0, "", "inlier share below: QUALITY_HIGH_RESIDUAL", &O::solver,
                &S::min_inlier_fraction)
        .scaled("max_dyaw_vs_ins_deg", M_PI / 180.0, 0.0, 180.0, "deg",
                "solved heading change farther from the INS heading change between the two frames: "
                "QUALITY_HEADING_CONTRADICTS (0: off)",
                &O::heading, &vo::HeadingCheckOptions::max_dyaw_vs_ins_rad)
        .number("homography_ransac_px", 0.01, 100.0, "px", "homography variant: RANSAC threshold", &O::solver,
                &S::homography_ransac_px)
        .number("feature_depth.max_relative_sigma", 1e-6, 1.0, "",
                "own depth used when its sigma is below this share of the depth", &O::solver, &S::feature_depth,
                &D::max_relative_sigma)
        .number("feature_depth.min_own_depth_features", 5, 10000, "",
                "fewer features with an own depth: the paper's model alone", &O::solver, &S::feature_depth,
                &D::min_own_depth_features)
        .number("feature_depth.anchor_radius", 1e-3, 2.0, "normalized image",
                "own depths within this radius of the altimeter beam anchor the scale", &O::solver,
                &S::feature_depth, &D::anchor_radius)
        .number("feature_depth.min_anchor_features", 3, 10000, "", "fewest own depths in the anchor fit",
                &O::solver, &S::feature_depth, &D::min_anchor_features)
        .number("feature_depth.scale_carry_pairs", 0, 1000, "pairs",
                "pairs in a row that keep the last anchored scale (0: never)", &O::solver, &S::feature_depth,
                &D::scale_carry_pairs)
        .flag("feature_depth.scale_filter", "fuse each anchored scale with the carried one by their variances",
              &O::solver, &S::feature_depth, &D::scale_filter)
        .number("feature_depth.scale_process_noise", 1e-6, 1.0, "", "scale filter: growth of the carried scale's sigma",
                &O::solver, &S::feature_depth, &D::scale_process_noise)
        .number("feature_depth.patch_feature_weight", 0.0, 1.0, "",
                "weight of a feature on the patch beside one with its own depth", &O::solver, &S::feature_depth,
                &D::patch_feature_weight)
        .number("feature_depth.triangulation_noise_px", 1e-3, 100.0, "px", "image noise assumed for track depths",
                &O::solver, &S::feature_depth, &D::triangulation_noise_px)
        .number("feature_depth.min_parallax_rad", 1e-6, 0.5, "rad", "below this parallax a track gives no depth yet",
                &O::solver, &S::feature_depth, &D::min_parallax_rad)
        .number("feature_depth.relative_process_noise", 0.0, 1.0, "", "floor of a depth's relative sigma",
                &O::solver, &S::feature_depth, &D::relative_process_noise)
        .number("feature_depth.max_epipolar_px", 1e-3, 100.0, "px",
                "tracks farther from their epipolar line give no depth", &O::solver, &S::feature_depth,
                &D::max_epipolar_px)
        .number("feature_depth.max_depth_jump_sigma", 1.0, 100.0, "",
                "a depth this many sigmas from the carried one restarts the track's depth", &O::solver,
                &S::feature_depth, &D::max_depth_jump_sigma)
        .flag("feature_depth.range_from_sample_position",
              "move an older altimeter range to where the aircraft was at the frame", &O::solver, &S::feature_depth,
              &D::range_from_sample_position)
        .number("feature_depth.ins_tilt_sigma_deg", 0.0, 5.0, "deg",
                "INS roll/pitch error of one frame, filtered per frame (0: tilt as the INS says)", &O::solver,
                &S::feature_depth, &D::ins_tilt_sigma_deg)
        .choice<vo::AnchorSurfaceModel>(
            "feature_depth.anchor_surface",
            {{"quadratic", vo::AnchorSurfaceModel::kQuadratic}, {"plane", vo::AnchorSurfaceModel::kPlane}},
            "surface fitted to the own depths around the beam", &O::solver, &S::feature_depth, &D::anchor_surface)
        .choice<vo::AnchorSpots>("feature_depth.anchor_spots",
                                 {{"beam", vo::AnchorSpots::kBeam}, {"track", vo::AnchorSpots::kTrack}},
                                 "where the altimeter meets the surface: the prev spot or the spots along the track",
                                 &O::solver, &S::feature_depth, &D::anchor_spots)
        .choice<bool>("dz_mode", {{"symmetric", true}, {"forward", false}},
                      "forward = eq. (7) on k-1 -> k only; symmetric = mean with the time-reversed pair", &O::solver,
                      &S::symmetric_dz)
        .choice<bool>("dyaw_start", {{"ins", true}, {"zero", false}},
                      "the fit starts at the INS heading change (ins) or at 0 (the paper's)", &O::solver,
                      &S::dyaw_start_from_ins)
        .include("uncertainty", DeltaUncertaintyOptions::schema(), &O::uncertainty)
        .choice<AttitudePolicy>("sync.attitude_policy",
                                {{"auto", AttitudePolicy::kAuto},
                                 {"interpolate", AttitudePolicy::kInterpolate},
                                 {"propagate", AttitudePolicy::kPropagate}},
                                "attitude at the trigger time: propagated where the INS reports body rates (auto), always, or interpolated between INS samples",
                                &O::sync, &Y::attitude_policy)
        .scaled("sync.ins_min_interval_ms", 1e3, 0.0, 1000.0, "ms", "propagate: INS samples are never closer",
                &O::sync, &Y::ins_min_interval_us)
        .scaled("sync.max_ins_gap_ms", 1e3, 0.001, 10000.0, "ms",
                "INS samples bracketing a frame farther apart: no attitude", &O::sync, &Y::max_ins_gap_us)
        .scaled("sync.max_ins_extrapolation_ms", 1e3, 0.0, 1000.0, "ms",
                "one-sided INS sample accepted this close to the frame", &O::sync, &Y::max_ins_extrapolation_us)
        .scaled("sync.altimeter_staleness_ms", 1e3, 0.001, 60000.0, "ms",
                "nearest valid range farther than this: stale (flagged)", &O::sync, &Y::altimeter_staleness_us)
        .scaled("sync.altimeter_wait_ms", 1e3, 0.0, 10000.0, "ms",
                "interpolate: INS time to wait for an altimeter sample after a frame", &O::sync,
                &Y::altimeter_wait_us)
        .scaled("sync.settle_ms", 1e3, 0.0, 10000.0, "ms", "extra sensor time to wait when a channel can reorder",
                &O::sync, &Y::settle_us)
        .choice<bool>("sync.altimeter_mode", {{"latest", false}, {"interpolate", true}},
                      "altimeter range at the frame: the latest sample or interpolated", &O::sync,
                      &Y::altimeter_interpolate)
        .scaled("sync.max_frame_interval_ms", 1e3, 0.001, 3600000.0, "ms", "prev -> curr longer: QUALITY_FRAME_GAP",
                &O::sync, &Y::max_frame_interval_us)
        .number("sync.max_pending_frames", 1, 10000, "", "TRACKS waiting for INS; the oldest is flushed flagged",
                &O::sync, &Y::max_pending_frames)
        .number("sync.max_ins_samples", 2, 1000000, "", "INS buffer size (oldest by utime dropped first)", &O::sync,
                &Y::max_ins_samples)
        .number("sync.max_altimeter_samples", 2, 1000000, "", "altimeter buffer size", &O::sync,
                &Y::max_altimeter_samples);
    return s;
  }();
  return schema;
}

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
  schema().read(c, &o);
  auto& t = o.sync;
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
