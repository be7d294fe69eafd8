#pragma once
// Options of the feature tracker, read from the `tracker:` section of the
// config. Every field has a default that matches the issue (450 Harris
// corners from a 3x3 grid, 21x21 KLT window, 3 pyramid levels, 1 px
// forward-backward threshold); Check() names the key and its allowed range.

#include <string>

#include "common/config.h"
#include "common/options_schema.h"

namespace nadir {

// How frames are paired (`tracker.mode`): KLT for the live camera, the
// descriptor matcher for photo surveys and other large motions, or KLT with
// the descriptor matcher per frame when KLT cannot follow (README.md).
enum class TrackerMode { kKlt, kDescriptor, kAuto };

// The descriptor matcher's options: the `tracker.descriptor:` subsection
// (descriptor_matcher.h, README.md "Descriptor matching").
struct DescriptorOptions {
  // orb | akaze | sift (OpenCV features2d). SIFT: the most pairs of the
  // real Seneca photos matched (81 of 98 against AKAZE's 63 and ORB's 58)
  // and sub-pixel keypoints; it costs the most (README.md "Descriptor matching").
  std::string type = "sift";
  int max_features = 1500;         // keypoints kept per frame ...
  int grid_cols = 6;               // ... spread over this grid: each cell keeps its strongest
  int grid_rows = 5;               //     max_features / cells, the rest go to the strongest left
  int border_px = 16;              // no keypoints closer to the image edge
  // Detector sensitivity, per type. Lower than OpenCV's defaults (20, 0.001,
  // 0.04): farmland seen from the air is weakly textured.
  int orb_fast_threshold = 10;
  // ORB's pyramid (scale factor 1.2): 4 levels cover scale changes up to
  // 1.7; every level coarsens the keypoint positions by another 20 %.
  int orb_levels = 4;
  double akaze_threshold = 0.0001;
  double sift_contrast_threshold = 0.01;
  // Candidate matches: Lowe's ratio test (best / second-best distance below
  // ratio; 1 = off) and the mutual-best cross check.
  double ratio = 0.85;
  bool cross_check = true;
  // Geometric check: RANSAC on the undistorted normalized coordinates,
  // `homography` (default: the ground is close to a plane at 40-1000 m, and a
  // point-to-point model rejects wrong matches that a fundamental matrix lets
  // through along their epipolar line - crop rows) or `fundamental`
  // (any 3-D scene, point-to-line). The threshold is in pixels at camera.fx
  // and loose: relief and lens error leave the plane by a few pixels.
  std::string geometry = "homography";
  double ransac_threshold_px = 8.0;
  double ransac_confidence = 0.999;
  int ransac_max_iterations = 10000;
  // Fewer candidates or inliers than this: no tracks (FLAG_FEW_FEATURES).
  int min_matches = 15;

  // Throws ConfigError naming `tracker.descriptor.<key>` and the allowed values.
  void Check(const std::string& source) const;
  static const OptionsSchema<DescriptorOptions>& schema();  // `tracker.descriptor:`
};

struct TrackerOptions {
  // `klt` (default, the live pipeline), `descriptor` or `auto`.
  TrackerMode mode = TrackerMode::kKlt;
  DescriptorOptions descriptor;
  // `auto`: a pair goes to the descriptor matcher when its sensor-time step
  // exceeds auto_max_interval_s, or when KLT keeps fewer than auto_min_tracks
  // tracks (then the same pair is matched again with descriptors).
  double auto_max_interval_s = 0.5;
  int auto_min_tracks = 40;

  // --- Detection: Harris corners per grid cell ---
  int grid_cols = 3;                // cells across the image
  int grid_rows = 3;                // cells down the image
  int features_per_cell = 50;       // target number of tracks per cell
  // A cell is topped up with new corners when it holds fewer than this many
  // tracks; below features_per_cell it saves detection work on most frames.
  int replenish_below = 45;
  double min_distance_px = 10.0;    // minimum spacing between any two features
  // No new corners this close to the image edge, and tracks that come this
  // close end: about half the KLT window, so the window reads real pixels.
  int border_px = 10;
  int harris_block_size = 3;        // neighbourhood of the structure tensor
  double harris_k = 0.04;
  // Corners weaker than quality_level x (strongest response in the cell) are
  // ignored, so every textured cell contributes (spatial spread)...
  double quality_level = 0.01;
  // ...but never weaker than this absolute response (cv::cornerHarris units,
  // gradients normalised to [0,1]): a featureless cell yields nothing rather
  // than noise corners.
  double min_harris_response = 1e-7;

  // --- Pyramidal Lucas-Kanade ---
  // Square window. Any size >= 5 works; lucas_kanade.cc processes window
  // rows in blocks of 8 pixels, so a size costs what the next multiple of 8
  // costs (21 as much as 24). 21 is the default.
  int klt_window_px = 21;
  int klt_pyramid_levels = 3;       // levels including full resolution
  int klt_max_iterations = 30;
  double klt_epsilon_px = 0.01;
  double klt_min_eig_threshold = 1e-4;  // cv::calcOpticalFlowPyrLK minEigThreshold
  // Scouted tracking. klt_scout_features tracks (an even spread) first go
  // through the full pyramid; the affine motion fitted to them predicts where
  // every other feature went, to well under a pixel on terrain seen from
  // altitude, so those need only klt_predicted_levels levels (1: full
  // resolution only - the same final refinement as the full pyramid's, a
  // third of its cost). A feature that fails that way (KLT lost or
  // forward-backward error too large) is tracked again with the full
  // pyramid. klt_predicted_levels = klt_pyramid_levels turns it off.
  int klt_scout_features = 48;
  int klt_predicted_levels = 1;
  // Resample each KLT template through the window's expected deformation
  // (the lens's local magnification at both ends and the pair's fitted image
  // motion), so that a translation-only KLT does not read the deformation as
  // a shift. Without it the shift biases grow with the step between frames:
  // a spurious expansion of the flow field that a solver takes for descent.
  // On by default since 2026-11-27 (README.md § Rough ground).
  bool klt_window_warp = true;
  // With klt_window_warp: a feature's warp is the last pair's linear map
  // around it (relief deforms windows differently across the image), fitted
  // to its neighbours' tracks within klt_local_warp_radius_px, weighted
  // (1 - d^2/r^2)^2; the lens-and-motion warp for features without one.
  bool klt_local_warp = false;
  double klt_local_warp_radius_px = 60.0;
  // Forward-backward check: a track survives when tracking it back from the
  // current frame lands within this distance of where it started.
  double fb_threshold_px = 1.0;
  // Levels the backward pass uses (<= klt_pyramid_levels). It starts at the
  // forward pass's start point, so a consistent track converges at once; the
  // coarse levels only widen the search for where a wrong match came from.
  // 2 levels (+-20 px) caught the same occlusion errors as 3 in the tests
  // at less cost (benchmark BM_FeatureTracker/synthetic/N).
  int fb_pyramid_levels = 2;
  // Window of the backward pass. It only has to confirm a match it starts
  // next to, so a much smaller window than the forward pass's does: 8 (one
  // block, see klt_window_px) rejects every occluded track in the tests and
  // cost 11 % fewer instructions per frame than 13.
  int fb_window_px = 8;
  // Photometric check: a track is dropped when its KLT patch error (mean
  // absolute grey difference over the window) exceeds
  // max(patch_error_floor, patch_error_factor x the frame's median).
  double patch_error_factor = 4.0;
  double patch_error_floor = 8.0;

  // --- Frame and image checks (node) ---
  int min_tracks = 20;              // fewer published tracks -> FLAG_FEW_FEATURES
  int dark_level = 8;               // pixel values <= this count as black
  int saturated_level = 250;        // pixel values >= this count as saturated
  double bad_pixel_fraction = 0.95; // this share black (or saturated) -> bad image
  double min_stddev = 2.0;          // grey-level std below this -> featureless
  int mono16_significant_bits = 16; // Mono16 -> 8 bit keeps the top 8 of these bits
  // A pair is flagged FRAME_GAP when the frame counters are not consecutive or
  // the sensor-time step exceeds gap_factor camera periods.
  double gap_factor = 1.5;
  // Beyond this sensor-time step the reference frame is too old to track
  // from: the tracker restarts (FLAG_FIRST_FRAME | FLAG_FRAME_GAP).
  double max_gap_s = 1.0;

  // Reads the `tracker:` section of the whole config (absent: defaults).
  static TrackerOptions from_config(const Config& root);
  // Throws ConfigError naming `tracker.<key>` and the allowed range.
  void Check(const std::string& source = "tracker options") const;
  static const OptionsSchema<TrackerOptions>& schema();  // every key of `tracker:` (options_schema.h)

  int max_features() const { return grid_cols * grid_rows * features_per_cell; }
};

}  // namespace nadir
