#pragma once
// Coasting: when the VO deltas are there but their translation
// cannot be trusted -- the altimeter range that scales them is missing or
// stale, the ground has no texture, the solve is bad -- yaw fusion does not
// integrate them. It coasts: the last good horizontal velocity, held in the
// level vehicle frame (so it follows the heading the INS measures), for at
// most coast.max_duration_s; the horizontal covariance grows with the model
// below. The climb rate is held too, in a height filter whose covariance
// grows the same way (coast_vertical_modes.h): over ground the last frames saw
// (seen_ground.h) each range measures the height and the climb; with
// follow_altimeter the height above the ground of the last integrated frames
// (coast_terrain.h) is weighted in elsewhere while there is a range.
//
// This file holds the pieces without state of the filter: the options, the
// covariance growth model and the detector that decides, delta by delta,
// whether to coast. The estimator (yaw_fusion_estimator.cc) does the rest.

#include <Eigen/Core>

#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <string>

#include "common/config.h"
#include "common/options_schema.h"
#include "nadir/vo_delta_t.hpp"

namespace nadir {

// Where a bridged coast's horizontal displacement comes from (coast.bridge_horizontal).
enum class BridgeHorizontal {
  kCoast,          // the held velocity turned with the INS heading, the coast's variance
  kPair,           // the pair across the coast as solved
  kPairDirection,  // the pair's direction, the coast's length: each the one that holds
};

struct CoastOptions {
  bool enabled = true;
  // VO_DELTA quality bits whose translation is coasted over (checked before
  // reject_quality_mask): TOO_FEW_FEATURES | NO_ALTIMETER | STALE_ALTIMETER.
  int32_t quality_mask = 1 | 2 | 4;
  // STALE_ALTIMETER (the solver's nearest range older than its 200 ms) is
  // coasted only when yaw fusion's own newest valid range is older than this:
  // one or two missed returns scale the motion with a range that is still right.
  double max_range_age_s = 0.5;
  double max_duration_s = 30.0;  // beyond, the old VO-gap behaviour (hold, FLAG_VO_GAP)
  // Covariance growth, each horizontal axis: the held velocity is off by a
  // constant error of velocity_stddev_mps plus a random walk of
  // velocity_random_walk_mps_per_sqrt_s (the aircraft's own accelerations),
  //   sigma_p^2(t) = sigma_v^2 t^2 + q^2 t^3 / 3.
  double velocity_stddev_mps = 0.5;
  double velocity_random_walk = 0.3;          // m/s per sqrt(s)
  double vertical_velocity_stddev_mps = 0.5;  // the same for down, with the same random walk
  // Texture loss / bad solves.
  double inlier_drop_fraction = 0.25;  // inliers below this fraction of the running median: coast
  int inlier_median_window = 50;       // integrated deltas in the running median (full before it is used)
  // dz against the altimeter: the ground under the vehicle moved by dz + (h_k - h_{k-1}) (down);
  // more than vertical_gate_m + vertical_gate_slope * horizontal step is not the ground: coast.
  double vertical_gate_m = 3.0;
  double vertical_gate_slope = 1.0;
  // ... and never below vertical_gate_sigmas robust sigmas of the ground steps
  // of the last inlier_median_window integrated deltas (MAD about zero, from
  // ten steps on): with a noisy altimeter (0.5 % of 300 m is 1.5 m per
  // range) the fixed gate alone coasted ~6 % of the frames of a good flight,
  // and each coast breaks the cancellation of the levelling errors that the
  // neighbouring deltas share. 0: the fixed gate only.
  double vertical_gate_sigmas = 5.0;
  int high_residual_window = 42;          // deltas (3 s at 14 Hz)
  double high_residual_fraction = 0.5;    // more than this fraction HIGH_RESIDUAL in the window: coast
  int resume_good_deltas = 3;             // clean deltas in a row before integrating again
  // The held velocity is the displacement over this window of integrated
  // positions, in the level vehicle frame of the mean heading the frames had
  // along it (held_level_velocity): per-frame attitude noise averages out,
  // and so does a heading oscillation the track does not follow.
  double speed_window_s = 3.0;
  // A delta solved with a stale range (STALE_ALTIMETER its only coasted bit,
  // no other reason) has the right direction and the wrong scale: coast at
  // the held horizontal speed along its direction (so a climb that steepens
  // while coasting is followed), |dz| at most max_climb_ratio of the
  // horizontal step. false: the held velocity for every coasted delta.
  bool vo_direction = true;
  double max_climb_ratio = 0.5;
  // While coasting with a valid range, the height is not the held climb's
  // alone: the ground of the last integrated frames (a plane through their
  // ground points, down + levelled height, tilted as the solver's ground
  // patch; coast_terrain.h) minus the levelled height now, weighted against
  // the held climb by their variances (range noise,
  // vo_solver.uncertainty.altimeter_stddev_*, and terrain_slope_stddev times
  // the distance; the coast model). false: the held climb rate alone.
  // Off by default: on held-out flights it ended closer only where a climb
  // starts or steepens in the coast, farther in level flight
  // (docs/research/2026-12-coasting.md).
  bool follow_altimeter = false;
  double terrain_window_s = 1.0;  // integrated frames that make the ground plane
  // Error of that plane's slope as the slope of the ground flown over while
  // coasting (m per m): the ground patch spans the image, the ground under the
  // coast is 100-200 m of hills. 1-s means of the patch slope against the
  // true slope along the track, test2 seed 102: 0.024 rms.
  double terrain_slope_stddev = 0.025;
  // While coasting with a valid range over ground the last integrated frame
  // saw (its VO_GROUND points, seen_ground.h; at least seen_ground_min_points
  // within seen_ground_radius_of_height x the height), the ground's height is known: each
  // range measures down = that ground minus the levelled range, where the
  // vehicle was when it was measured, in the coast's height filter
  // (coast_vertical_modes.h), which holds the climb from the frames before and
  // measures it over the seen ground; beyond it the filter's climb is held.
  // Independent of follow_altimeter (the plane
  // is used only beyond the seen ground, and only with it). On by default:
  // over 33 flights with a 10 s texture outage, where a climb starts in the
  // coast the final height was 2.6-4.6 m closer than with the held climb on
  // test2 (0.8-7 m over rough relief), in level flight up to 2 m farther
  // (docs/research/2026-12-coasting.md).
  bool follow_seen_ground = true;
  double seen_ground_window_s = 1.0;  // integrated frames whose points are kept (each track's newest)
  // The points within this share of the height (the levelled range; at
  // least 10 m) make the ground below: the points thin out as the height
  // grows (the same features over a larger footprint). 0.17: 25 m at 150 m.
  double seen_ground_radius_of_height = 0.17;
  int seen_ground_min_points = 8;
  // Over seen ground the climb can have two models (coast_vertical_modes.h):
  // steady -- the held climb stays, to within this error and random walk --
  // and changing -- vertical_velocity_stddev_mps and velocity_random_walk,
  // the coast model's. The ranges' downs weigh them, starting from this
  // chance that the climb is changing and switching at this rate each way.
  // Without seen ground at the coast's start: the changing model alone. The
  // default is the changing model alone (probability 1, rate 0): on 16
  // held-out flights the two models ended about where it does (mean |final vertical|
  // 0.60 against 0.62 m) and one rough-relief coast in 33 ended beyond 3
  // sigma with them (docs/research/2026-12-coasting.md, "Two models of the
  // climb"); 0.5 and 0.02 give the two.
  double seen_ground_steady_climb_stddev_mps = 0.05;
  double seen_ground_steady_random_walk = 0.02;  // m/s per sqrt(s)
  double seen_ground_changing_probability = 1.0;
  double seen_ground_switch_rate = 0.0;  // 1/s
  // When VO returns, a delta from the last integrated frame over the whole
  // coast (tracker.mode auto matches the first good frame after featureless
  // ones with the last good one while their footprints still overlap) ends
  // the coast: the filter goes back to that frame and integrates the delta's
  // climb and ground tilt, the INS's heading change over it, and a horizontal
  // step along the pair's direction as long as the coast's -- on 15 flights
  // with a 10 s texture outage the delta's climb was 0.15 m rms off where the
  // coast's height was up to 3.7 m off, its length 0.05-5.6 % off where the
  // held velocity's was within 0.3 %, and the held velocity's direction off by
  // the heading's swing about the track (docs/research/2026-12-coasting.md,
  // "Matched across the coast", "The pair's direction, the coast's length, the
  // INS's turn").
  // bridge_horizontal: whose horizontal -- the coast's (displacement and
  // variance), the pair's own, or the pair's direction with the coast's
  // length (the coast's variance along it, the pair's across).
  // bridge_heading_from_ins: the pair's heading change is replaced by the
  // INS's over the same span, and its horizontal step moves with it (its
  // covariance's regression on dyaw). A strip of common ground far from the
  // nadir tells a turn from a sideways step poorly: the pairs' dyaw was
  // 0.3-1.1 deg off where they reported 0.06 deg, and their sideways step
  // off by that angle times the strip's distance.
  bool bridge = true;
  BridgeHorizontal bridge_horizontal = BridgeHorizontal::kPairDirection;
  bool bridge_heading_from_ins = true;

  // Reads yaw_fusion.coast (keys named with their full path on error).
  static CoastOptions from_config(const Config& coast);
  void Check() const;  // throws ConfigError naming the key
  static const OptionsSchema<CoastOptions>& schema();
};

// One integrated frame as the held velocity sees it: its time, position
// (NED) and fused yaw (rad).
struct CoastSample {
  int64_t utime = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw = 0.0;
};

// The velocity a coast holds, in the level vehicle frame (x forward, y right,
// z down): the displacement from the first sample of `window` to the last
// over its duration, turned into the frame of the mean heading of the frames
// that displacement was registered with (every sample but the last; each
// delta is registered with its previous frame's yaw). Turned back with the
// heading of each coasting frame it gives the track the window flew, with
// the angle between track and heading (crab, sideslip, a heading
// oscillation the track does not follow) as it was on average over the
// window rather than at its last frame. Needs two samples with increasing
// times; nullopt otherwise.
std::optional<Eigen::Vector3d> held_level_velocity(const std::deque<CoastSample>& window);

// Position variance (m^2, one axis) after coasting t seconds with velocity
// error sigma_v (m/s) and random walk q (m/s per sqrt s). 0 for t <= 0.
double coast_position_variance(double sigma_v, double q, double t);

// Why a delta is coasted over (bitmask; 0 = integrate it).
enum CoastReason : int32_t {
  kCoastQuality = 1,       // a bit of quality_mask (no/stale altimeter, no features)
  kCoastInlierDrop = 2,
  kCoastVertical = 4,      // dz inconsistent with the altimeter
  kCoastHighResidual = 8,  // HIGH_RESIDUAL majority over the window
  kCoastResuming = 16,     // clean, but fewer than resume_good_deltas in a row yet
};
inline constexpr int kCoastReasons = 5;
const char* coast_reason_name(int bit);

// Decides per delta whether to coast. Feed every delta that reaches the
// filter in order; note_integrated() the ones that were integrated.
class CoastDetector {
 public:
  explicit CoastDetector(const CoastOptions& options) : options_(options) {}

  // `coast_bits`: the delta's quality bits that are coasted over (quality_mask,
  // less a stale altimeter flag the range age does not confirm);
  // `height_change_m` = h_k - h_{k-1} from the altimeter (NaN when either is unknown).
  int32_t classify(const vo_delta_t& delta, int32_t coast_bits, double height_change_m, bool coasting);
  void note_integrated(const vo_delta_t& delta);
  double inlier_median() const;  // NaN until the window is full
  // The vertical gate for a delta with this horizontal step (metres).
  double vertical_gate(double horizontal_m) const;

 private:
  CoastOptions options_;
  std::deque<int> inliers_;          // of integrated deltas
  std::deque<double> ground_steps_;  // of integrated deltas (finite ones)
  double last_ground_step_ = std::numeric_limits<double>::quiet_NaN();  // of the delta classified last
  std::deque<bool> high_residual_;   // of all classified deltas
  int high_residual_count_ = 0;
  int good_streak_ = 0;
};

}  // namespace nadir
