#pragma once
// Options of the feature_depth solver variant (DERIVATION.md section 13):
// which own depths are trusted, how they are re-anchored on the altimeter,
// and how the per-track depth filter (FeatureDepthMap) updates.

#include <cmath>

namespace nadir::vo {

// The surface fitted to the own depths around the altimeter beam (inverse
// depth over the ray's offset from the beam): a plane, or a quadratic that
// follows a crest or a valley under the spot (DERIVATION.md section 13).
enum class AnchorSurfaceModel { kPlane, kQuadratic };

// Where the altimeter meets the surface: at the prev frame's spot alone, or
// at the spots of the frames before it along the track (2 x anchor_radius
// back), each weighted as the fit weighs the own depths there, so that the
// surface's misfit to a sharp crest averages out instead of biasing the
// scale (DERIVATION.md section 13).
enum class AnchorSpots { kBeam, kTrack };

struct FeatureDepthOptions {
  // A feature's own depth is used when its standard deviation is below this
  // share of the depth; else the ground patch gives its depth.
  double max_relative_sigma = 0.03;
  // At least this many features with a usable own depth, else the pair is
  // solved by the paper's model alone (identical to variant paper).
  int min_own_depth_features = 30;
  // Altimeter anchor: a surface fitted to the own-depth points whose level
  // rays lie within this radius (normalized image units, about 0.25 * focal
  // px) of the altimeter beam gives the structure's range along the beam; the
  // altimeter's range over it is the scale of every own depth. At least
  // min_anchor_features of them (and twice the surface's unknowns), else the
  // paper's model alone.
  double anchor_radius = 0.25;
  int min_anchor_features = 8;
  // Where even the plane finds too few own depths within anchor_radius (low
  // over a crest, where the image holds less ground, or where the tracks
  // near the beam are young), the pair keeps the own depths at the scale the
  // pair before left them, for up to this many pairs in a row after one the
  // altimeter anchored; then the paper's model alone. Over relief the
  // paper's one plane is a step off where the map is exact (0: never).
  int scale_carry_pairs = 14;
  // The scale filter: each anchored pair's altimeter scale is fused with the
  // scale the own depths carry (the pair before's, its variance grown by
  // scale_process_noise^2), by their variances. The anchor's variance is its
  // fit's plus the surface's model error near the beam: how far the own
  // depths there miss the fitted surface beyond their own sigmas (a sharp
  // crest the quadratic cannot hold). false: every anchored pair takes the
  // altimeter's scale as it is.
  bool scale_filter = false;
  double scale_process_noise = 1e-4;
  AnchorSurfaceModel anchor_surface = AnchorSurfaceModel::kQuadratic;
  AnchorSpots anchor_spots = AnchorSpots::kBeam;
  // Weight of a feature on the patch (young) beside one with its own depth,
  // where the patch holds the own depths within their sigmas; divided by the
  // square of the patch's misfit to them where that is above 1 (relief).
  double patch_feature_weight = 1.0;
  // Depth of a track (from its first ray against the curr one): image noise
  // assumed (pixels), the parallax (rad) below which the track says nothing
  // about depth yet (hover), the floor of a depth's relative sigma (the error
  // of the solved motion its baseline is made of), and the distance (pixels)
  // of a track from its epipolar line beyond which it is not on a static
  // surface (moving object, mismatch): no depth from that pair.
  double triangulation_noise_px = 0.5;
  double min_parallax_rad = 1e-3;
  double relative_process_noise = 0.002;
  double max_epipolar_px = 2.0;
  // A pair's triangulated depth this many combined sigmas from the carried
  // one: the surface under the track changed (cliff edge); restart from the pair.
  double max_depth_jump_sigma = 5.0;
  // Each frame's altimeter range and beam as seen from the camera at the
  // frame: a range older than its frame (altimeter_mode latest, up to one
  // altimeter period) is moved from where the aircraft was when it was
  // sampled, with the velocity of the pairs before (range_at_frame.h).
  // Without it a climb, a descent or a slope under the beam biases each
  // pair's scale by range rate x age / range.
  bool range_from_sample_position = true;
  // The INS roll/pitch error of one frame (sigma, degrees, white from frame
  // to frame). Each pair fits the tilt between its two frames to the images,
  // and a filter keeps each frame's own tilt error from those tilts and the
  // INS (this sigma): a pair's tilt is the difference of its frames' errors,
  // so the sideways image motion a tilt error leaves still telescopes. Without
  // it (0) the tilt is taken as the INS says, and its image motion is read as
  // translation: first order across the image (it telescopes) and, to second
  // order, as a climb of about height x tilt^2 in every pair, which does not
  // (DERIVATION.md section 13).
  double ins_tilt_sigma_deg = 0.05;
  // The same as a variance, rad^2 (the filter's and a new map's).
  double ins_tilt_variance() const { return std::pow(ins_tilt_sigma_deg * M_PI / 180.0, 2); }
  // Throws std::invalid_argument naming the field and the allowed range.
  void Check() const;
};

}  // namespace nadir::vo
