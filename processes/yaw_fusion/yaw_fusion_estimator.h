#pragma once
// Yaw fusion without a bus: takes VO_DELTA, INS and ALTIMETER messages in any
// arrival order, synchronises them by sensor time, runs the PoseFilter and
// returns POSE messages in frame order.
//
// Order robustness: a delta is processed only once INS covering its utime is
// there (an INS sample with utime >= the delta's) and an altimeter sample
// covering it (or altimeter_wait_s of sensor time has passed), or once the
// newest sensor time seen is ins_wait_s past it. Deltas are processed in utime
// order. A live run and a lockstep replay of the same messages therefore give
// identical poses as long as no message is later than those waits.
//
// VO gaps: a missing delta (prev_utime after the last frame) or a rejected one
// (invalid values or a quality bit in reject_quality_mask) is bridged by dead
// reckoning with the last world velocity for up to gap.max_propagation_s, then
// by holding the position; the position variance grows as if that velocity
// were off by gap.velocity_stddev_mps for the whole gap. While no delta comes,
// gap poses are published at the camera rate (driven by INS sensor time), and
// the delta that ends a gap first gets a pose at its prev_utime; all of these
// carry FLAG_VO_GAP.
//
// Coasting (coasting.h): a delta that comes but whose translation is not
// trusted (no or stale altimeter, no features, inlier drop, dz against the
// altimeter, HIGH_RESIDUAL majority) is not integrated; the pose coasts on the
// last velocity held in the level vehicle frame, flagged FLAG_COASTING, its
// covariance grown by the coast model, for up to coast.max_duration_s. Over
// ground the last integrated frames saw (VO_GROUND, seen_ground.h) each range
// measures the height (that ground minus the levelled range) in the coast's
// height filter (coast_vertical_modes.h: a steady and a changing climb;
// coast.follow_seen_ground). When VO returns and its first delta starts at
// the last integrated frame (the tracker matched across the featureless
// ground), the filter goes back there and integrates it with the INS's
// heading change and the coast's length along its direction: its climb ends
// the coast's vertical error (coast.bridge).
//
// Map fixes (MAP_FIX): a fix z of the frame at t_f, whose pose had position
// x_f and reported horizontal covariance P_f, is applied at the first pose at
// or after t_f + map_fix.apply_delay_s as a delayed measurement: with the
// motion since t_f independent of the error at t_f, the position now moves by
// M S^-1 (z - x_f) and its covariance loses M S^-1 M', M = P_f - C,
// S = P_f - C - C' + B + R (R the fix's covariance). B is the map's error
// common to all its fixes (map_fix.systematic_stddev_m^2 each axis), kept as
// a consider parameter (Schmidt): never estimated, but C, the position
// error's covariance with it, is carried from fix to fix (C <- (I - K) C + K B,
// K = M S^-1), so that a thousand fixes do not average the map's own error
// away. A fix with the DEM's ground under it (map_fix.vertical) is a
// three-axis measurement: its down is that ground, carried along its slope to
// the altimeter's spot at t_f, less the levelled range there; the fix's
// horizontal error moves it along the slope (so its covariance couples the
// axes, and so does the map's horizontal error through G below), and its
// variance adds the DEM's and the range's. With z = H x + G b + v (H picks
// the axes measured, G = [I 0; slope' 1] for three), M = P_f H' - C G',
// S = H P_f H' - H C G' - G C' H' + G B G' + R, C <- (I - K H) C + K G B. A
// fix whose innovation is beyond map_fix.gate_sigma (Mahalanobis) is rejected. The pose it is applied at
// (or rejected at) carries FLAG_MAP_FIX_APPLIED (FLAG_MAP_FIX_REJECTED).
//
// Start: the pose origin is the first frame of the first usable delta. Deltas
// before it that cannot be used (flagged, e.g. no altimeter yet) publish no
// pose: there is no motion to dead-reckon yet, and an origin set there would
// lose the motion until VO works (counted in vo_deltas_before_start).

#include <Eigen/Core>

#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "nadir/altimeter_t.hpp"
#include "nadir/ground_points_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/map_fix_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/vo_delta_t.hpp"
#include "processes/yaw_fusion/checkpoint.h"
#include "processes/yaw_fusion/coast_terrain.h"
#include "processes/yaw_fusion/coast_vertical_modes.h"
#include "processes/yaw_fusion/coasting.h"
#include "processes/yaw_fusion/fix_consistency.h"
#include "processes/yaw_fusion/delta_integration.h"
#include "processes/yaw_fusion/pose_filter.h"
#include "processes/yaw_fusion/seen_ground.h"
#include "processes/yaw_fusion/sensor_history.h"
#include "processes/yaw_fusion/yaw_fusion_options.h"

namespace nadir {

struct YawFusionCounters {
  int64_t vo_deltas_received = 0;
  int64_t vo_deltas_integrated = 0;
  int64_t vo_deltas_invalid = 0;           // bad timing or non-finite values (named in last_problem)
  int64_t vo_deltas_quality_rejected = 0;  // a quality bit in reject_quality_mask
  int64_t vo_deltas_before_start = 0;      // unusable deltas before the first usable one (no pose)
  int64_t vo_deltas_duplicate = 0;
  int64_t vo_deltas_late = 0;              // arrived after their frame time was already published
  int64_t vo_deltas_without_ins = 0;       // processed on timeout, INS not covering them
  int64_t ins_received = 0;
  int64_t ins_invalid = 0;
  int64_t ins_duplicate = 0;
  int64_t ins_yaw_updates = 0;
  int64_t ins_yaw_rejected = 0;
  int64_t ins_yaw_unusable = 0;            // no INS yaw at a frame, or its stddev too large
  int64_t yaw_reinitialised = 0;
  int64_t yaw_from_ins_in_gap = 0;  // INS yaw taken ungated during a VO gap
  int64_t altimeter_received = 0;
  int64_t altimeter_invalid = 0;           // validity != OK or non-finite
  int64_t altimeter_rejected = 0;          // gated: level_terrain: terrain re-anchored; barometric: not used
  int64_t altimeter_down_resets = 0;       // barometric: down reset to the barometric height
  int64_t frames_without_altimeter = 0;
  int64_t gap_bridges = 0;                 // gaps closed by a delta starting after the last pose
  int64_t gap_poses = 0;                   // poses without VO: at the camera rate in a gap, and at
                                           // the first frame of the delta that closes it
  int64_t gap_poses_superseded = 0;        // gaps whose dead-reckoned poses a late continuous delta replaced
  int64_t time_jumps_dropped = 0;         // messages far ahead of all sensor time (see max_time_jump_s)
  int64_t resumed = 0;                     // 1 when the run continued from a checkpoint
  int64_t vo_deltas_coasted = 0;           // deltas whose translation was not integrated (coasting)
  int64_t coast_reasons[kCoastReasons] = {};  // per CoastReason bit (coast_reason_name)
  int64_t coast_episodes = 0;
  int64_t coast_expired = 0;               // deltas after coast.max_duration_s (VO gap instead)
  int64_t coast_ground_steps = 0;          // coasting on the altimeter: range jumps taken as the ground's
  int64_t ground_frames_received = 0;      // VO_GROUND messages (kept only with coast.follow_seen_ground)
  int64_t coast_seen_ground_poses = 0;     // coasting poses whose down came from ground a frame saw
  int64_t coasts_bridged = 0;              // coasts a delta from the last integrated frame ended (coast.bridge)
  int64_t deltas_reverted = 0;             // integrating would have made the state non-finite
  int64_t map_fixes_received = 0;
  int64_t map_fixes_invalid = 0;           // non-finite, a covariance not positive definite, or disabled
  int64_t map_fixes_applied = 0;
  int64_t map_fixes_rejected = 0;          // gated
  int64_t map_fixes_unmatched = 0;         // no pose at the fix's frame (or too old)
  int64_t map_fixes_late = 0;              // came after the pose it was due at
  int64_t map_fixes_with_height = 0;       // of those applied, with the DEM's ground (map_fix.vertical)
  int64_t map_fix_heights_rejected = 0;    // applied, but the height gated out (horizontal only)
  int64_t poses = 0;
  std::string last_problem;                // names the channel, utime and reason
};

class YawFusionEstimator {
 public:
  explicit YawFusionEstimator(const YawFusionOptions& options);

  // Each returns the poses that became ready, in frame order.
  std::vector<pose_t> add_vo_delta(const vo_delta_t& delta);
  std::vector<pose_t> add_ins(const ins_t& ins);
  std::vector<pose_t> add_altimeter(const altimeter_t& altimeter);
  // The ground points a frame saw (VO_GROUND): kept for the coast that may
  // follow once that frame's delta is integrated (coast.follow_seen_ground).
  void add_ground_points(const ground_points_t& points);
  // Queues a fix; it is applied with the pose it is due at (see above).
  void add_map_fix(const map_fix_t& fix);

  // Continue from `last` (the POSE a previous run published last, from its
  // checkpoint) instead of a new origin: at the first usable delta the
  // position is `last` dead-reckoned with its velocity over the time between
  // (at most gap.max_propagation_s), its covariance grown as for a VO gap, and
  // that pose is flagged FLAG_VO_GAP. Ignored (fresh start, named in
  // last_problem) when the first delta is before `last` or more than
  // gap.max_duration_s after it. A checkpoint with the heading bias
  // (heading_bias_* of a yaw_fusion_checkpoint_t) restores the bias that map
  // fixes estimated; without it the bias starts again from its prior.
  void resume_from(const pose_t& last) { resume_from(checkpoint_without_bias(last)); }
  void resume_from(const yaw_fusion_checkpoint_t& last) { resume_ = last; }
  // What a checkpoint keeps after `pose` was published: the pose and the
  // heading bias as it is now.
  yaw_fusion_checkpoint_t checkpoint(const pose_t& pose) const;

  const YawFusionCounters& counters() const { return counters_; }
  const PoseFilter& filter() const { return filter_; }
  size_t pending_deltas() const { return pending_.size(); }
  bool started() const { return started_; }
  // True while no delta has been integrated for longer than gap.max_duration_s.
  bool vo_lost() const;

 private:
  // The INS attitude at a frame (stamp) time's exposure time under the configured attitude policy.
  std::optional<AttitudeSample> ins_attitude_at(int64_t utime) const;
  // The INS pitch (rad, NaN when the INS does not bracket it) of the frame at this sensor time, and the
  // share of one sample's white noise in its attitude.
  FrameAttitudeNoise frame_attitude_noise(int64_t utime) const;
  bool delta_ready(const vo_delta_t& delta) const;
  void pump(std::vector<pose_t>* out);
  void start(const vo_delta_t& first, std::vector<pose_t>* out);
  // Restores the filter from resume_ for a start at t0; false if too old or in the future.
  bool resume(int64_t t0);
  void process_delta(const vo_delta_t& delta, std::vector<pose_t>* out);
  // Dead-reckons from the last frame to `utime` and updates yaw there; returns pose flags.
  int32_t advance_without_vo(int64_t utime);
  // Coasts from the last frame to `utime` (not integrating a delta); returns
  // pose flags. `direction`: a delta whose direction (not scale) is used.
  int32_t coast_to(int64_t utime, const vo_delta_t* direction = nullptr);
  // The held level velocity flown from `from` to `to`, turned with the heading
  // the INS measured along the way (the fused yaw at `from` plus the INS's
  // turn since), in steps of at most 0.1 s: a photo flight's frames can be
  // many seconds apart, through a turn. `velocity_at_end`: the world velocity at `to`.
  Eigen::Vector3d coast_displacement(int64_t from, int64_t to, const Eigen::Vector3d& level_velocity,
                                     Eigen::Vector3d* velocity_at_end) const;
  // While coasting with a valid range at `utime`: over seen ground, the down
  // measured there updates the height filter; else, with a terrain plane, down =
  // the height filter's and the terrain's (the plane below the coasted
  // position minus the levelled height) weighted by their variances. A terrain down more than the vertical gate for
  // this horizontal step from where the last pose and the held climb put it
  // is the ground stepping: the plane moves by the step. False (nothing
  // changed) without a range or a plane.
  bool follow_altimeter(int64_t utime, double horizontal_step_m);
  // Reason bits (CoastReason) for coasting over this usable delta; 0 = integrate it.
  int32_t coast_reason(const vo_delta_t& delta, int32_t coast_bits);
  bool held_speed_ready() const;  // coasting, or speed_window_s of integrated motion behind the pose
  // The delta's quality bits coasted over: coast.quality_mask, less
  // STALE_ALTIMETER when a valid range within coast.max_range_age_s is there.
  int32_t coast_bits(const vo_delta_t& delta) const;
  // Levelled altimeter height at a frame time, NaN without a fresh range.
  double altimeter_height_at(int64_t utime) const;
  // The levelled range as a vector (x forward, y right, z down = the height), NaN without a fresh range.
  Eigen::Vector3d altimeter_beam_at(int64_t utime) const;
  // INS yaw update at `utime`; returns pose flags; fills the attitude used.
  int32_t update_attitude(int64_t utime);
  int32_t update_height(int64_t utime, double fallback_height);
  // barometric: a height above the datum (the terrain state, anchored once)
  // updates down, gated; altimeter_max_consecutive_rejections in a row reset it.
  void update_barometric(int64_t utime, double height);
  pose_t make_pose(int64_t utime, int32_t flags) const;
  // Applies (or gates out) the queued fixes due at a pose at `utime`; returns pose flags.
  int32_t apply_due_map_fixes(int64_t utime);
  int32_t apply_map_fix(const map_fix_t& fix);
  void remember_poses(const std::vector<pose_t>& poses, size_t from);
  bool delta_values_valid(const vo_delta_t& delta, std::string* why) const;
  bool delta_quality_ok(const vo_delta_t& delta) const { return (delta.quality & options_.reject_quality_mask) == 0; }
  // Usable to start from: not rejected, and not one coasting would skip.
  bool delta_usable(const vo_delta_t& delta) const {
    std::string why;
    const bool coast = options_.coast.enabled && (delta.quality & options_.coast.quality_mask) != 0;
    return delta_quality_ok(delta) && !coast && delta_values_valid(delta, &why);
  }
  void note_problem(const std::string& text) { counters_.last_problem = text; }
  // False for a utime far ahead of all sensor time seen, unless the previous
  // such message on the same channel (its candidate) agrees with it.
  bool plausible_time(int64_t utime, int64_t* candidate, const char* channel);
  // A delta from the last integrated frame, continuous (no frame gap), that
  // arrives after gap poses were dead-reckoned over its span: the next photo of
  // a survey later than the camera period. It replaces them (the filter goes
  // back to the last integrated frame) instead of being dropped as late.
  bool supersedes_gap_poses(const vo_delta_t& delta) const;
  // While coasting, a usable delta from the last integrated frame to after
  // the last pose: the tracker (mode auto) matched its last good frame with
  // the first after the featureless ground. It ends the coast: the filter
  // goes back to that frame and integrates bridge_delta(it) (coast.bridge).
  bool bridges_coast(const vo_delta_t& delta) const;
  // From the last integrated frame, no longer than a coast may last, with
  // coast.bridge on: it may end a coast, so it may span more than
  // max_delta_interval_s.
  bool may_bridge_a_coast(const vo_delta_t& delta) const;
  // The delta as integrated over a coast: its climb and ground tilt, the
  // INS's heading change (coast.bridge_heading_from_ins), and the horizontal
  // displacement and variance coast.bridge_horizontal names.
  vo_delta_t bridge_delta(const vo_delta_t& delta) const;
  // The INS's heading change between two frames' exposures and its variance
  // (both ends' and the bias walk's over the span); none without INS at both.
  struct Turn {
    double dyaw;
    double variance;
  };
  std::optional<Turn> ins_turn(int64_t from, int64_t to) const;
  std::optional<vo_delta_t> next_bridge_;  // the pending delta that bridges the coast, as integrated

  YawFusionOptions options_;
  PoseFilter filter_;
  InsHistory ins_;
  AltimeterHistory altimeter_;
  std::map<int64_t, vo_delta_t> pending_;  // by utime
  YawFusionCounters counters_;

  int64_t sensor_now_;             // newest sensor time seen on any input
  int64_t vo_jump_candidate_, ins_jump_candidate_, altimeter_jump_candidate_;
  bool started_ = false;
  int64_t last_frame_utime_ = 0;   // time of the last published pose (frame or gap)
  int64_t last_good_utime_ = 0;    // time of the last integrated delta (or the origin)
  PoseFilter good_filter_;         // the filter as published at last_good_utime_
  Eigen::Vector3d last_velocity_ = Eigen::Vector3d::Zero();  // world, over the velocity window
  std::deque<std::pair<int64_t, Eigen::Vector3d>> recent_positions_;  // for the velocity window
  Eigen::Vector3d velocity_out_ = Eigen::Vector3d::Zero();   // published velocity
  double roll_ = 0.0, pitch_ = 0.0;  // INS attitude at the last frame
  double height_agl_ = 0.0;
  bool have_height_ = false;
  bool yaw_from_ins_ = false;      // the yaw has taken at least one INS measurement
  // A VO gap: nothing but the INS measures the yaw, so its next yaw is taken
  // as it is, not gated against a prediction that knows no turn.
  bool yaw_without_vo_ = false;
  int consecutive_yaw_rejections_ = 0;
  int consecutive_altimeter_rejections_ = 0;       // barometric
  int good_consecutive_altimeter_rejections_ = 0;  // ... as at last_good_utime_ (with good_filter_)
  double good_altimeter_height_ = std::numeric_limits<double>::quiet_NaN();  // last_altimeter_height_ then
  int64_t frames_ = 0;
  std::optional<yaw_fusion_checkpoint_t> resume_;
  // Coasting: the velocity held in the level vehicle frame (x forward, y right,
  // z down) at the last integrated frame, whose time starts the coast.
  CoastDetector coast_detector_;
  std::deque<CoastSample> coast_positions_;  // integrated frames, over coast.speed_window_s
  bool coasting_ = false;
  Eigen::Vector3d coast_velocity_level_ = Eigen::Vector3d::Zero();
  double last_altimeter_height_ = std::numeric_limits<double>::quiet_NaN();  // at the last frame
  // The ground while coasting (coast.follow_altimeter): the integrated frames'
  // ground points and patch tilts, anchored when a coast starts.
  CoastTerrain coast_terrain_;
  // The height while coasting (coast_vertical_modes.h): down and climb from
  // the last integrated frame, the climb held, measured over seen ground.
  CoastVerticalModes coast_vertical_;
  // Ground points by frame time until their delta is integrated; the ground
  // the last integrated frame saw.
  std::map<int64_t, ground_points_t> pending_ground_;
  SeenGround seen_ground_;  // declared after coast_terrain_ (constructor order)
  bool on_seen_ground_ = false;  // the last coasting pose's down was measured over seen ground
  Eigen::Vector3d last_seen_ground_ = Eigen::Vector3d::Zero();  // north, east and ground down there
  // A range sample placed for the seen ground: where the vehicle was when it
  // was measured (the frame's position less the velocity since), the frame's
  // heading, and the range levelled with the INS at its own time, as a vector.
  struct PlacedRange {
    int64_t utime = 0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double yaw = 0.0;
    Eigen::Vector3d beam = Eigen::Vector3d::Zero();
  };
  // The valid ranges from the exposure of the frame at `prev_utime` up to
  // (not at) the exposure of the one at `utime`, whose position and velocity
  // are given.
  std::vector<PlacedRange> place_ranges(int64_t prev_utime, int64_t utime, const Eigen::Vector3d& position,
                                        const Eigen::Vector3d& velocity) const;
  std::deque<PlacedRange> recent_ranges_;  // of the integrated frames over coast.seen_ground_window_s
  int64_t last_range_utime_ = 0;           // the last range the coast placed (0: none yet)
  // Each range since the last frame over seen ground updates the height
  // filter with the down measured there (that ground minus the levelled
  // range), which ends at the coast time of `utime` in any case. True when
  // the pose is over seen ground (a range was used, or none came since a
  // frame that was); `position` and `velocity` the coast's at `utime`, `e0`
  // the last frame's coast time.
  // `direction_climb`: the climb of a stale-range delta's direction, when followed.
  bool follow_seen_ground(int64_t utime, const Eigen::Vector3d& position, const Eigen::Vector3d& velocity, double e0,
                          std::optional<double> direction_climb);
  // The seen ground's fit where the beam of a vehicle at `position` with
  // `yaw` and levelled range `beam` hits it (`spot`, and the radius of the
  // fit); nullopt where it was not seen.
  std::optional<SeenGround::Height> seen_ground_below(const Eigen::Vector3d& position, double yaw,
                                                      const Eigen::Vector3d& beam, Eigen::Vector2d* spot,
                                                      double* radius = nullptr) const;
  // When a coast starts: the offset of the seen ground's fit from where the
  // last integrated frames' ranges put the ground under their beams. False
  // when none of those ranges was over seen ground.
  bool anchor_seen_ground();
  double seen_ground_offset_ = 0.0;
  // Past the seen ground: the plane of follow_altimeter (when anchored) goes
  // on from the last ground seen.
  void leave_seen_ground();
  // Map fixes waiting for their pose, by frame time; the poses published over
  // the last few seconds (utime, horizontal position, reported covariance).
  std::multimap<int64_t, map_fix_t> pending_fixes_;
  struct PublishedPose {
    int64_t utime;
    Eigen::Vector3d position;
    Eigen::Matrix3d covariance;
    // The levelled range at the frame turned to north/east/down (its z the
    // height above ground); NaN without a range.
    Eigen::Vector3d range_ned;
    // PoseFilter::yaw_bias_cross() when the pose was published.
    Eigen::Matrix2d yaw_bias_cross;
  };
  std::deque<PublishedPose> published_;
  // With map_fix.estimates_heading_bias: moves the INS heading bias estimate
  // by a horizontal fix of the pose `at` (its innovation, S^-1,
  // cov(position error, innovation) north/east, and the map's systematic
  // error's covariance `map_bias` with the frame's position error's
  // covariance with it before the fix) and returns the position's covariance
  // with the bias error after the fix (PoseFilter::hold_yaw_bias_correlation).
  std::optional<Eigen::Matrix2d> estimate_heading_bias(const PublishedPose& at, const Eigen::Vector2d& innovation,
                                                       const Eigen::Matrix2d& s_inverse,
                                                       const Eigen::Matrix2d& error_innovation,
                                                       const Eigen::Matrix3d& map_bias,
                                                       const Eigen::Matrix3d& frame_map_cross);
  // The bias error's covariance with the map's systematic error (rows walk,
  // markov), as of the sensor time beside it: a map's offset seen from a
  // turning aircraft is not taken for a heading bias twice.
  Eigen::Matrix<double, 2, 3> bias_map_cross_ = Eigen::Matrix<double, 2, 3>::Zero();
  int64_t bias_map_cross_utime_ = 0;
  // update_height's levelled ranges by frame time (north/east/down), for the
  // poses remember_poses keeps.
  std::deque<std::pair<int64_t, Eigen::Vector3d>> frame_ranges_;
  // Covariance of the position error (north, east, down) with the map's
  // systematic error (the consider parameter of the map fixes): zero until a fix.
  Eigen::Matrix3d map_error_cross_ = Eigen::Matrix3d::Zero();
  // Whether the pose's covariance holds what the fixes see (fix_consistency.h).
  FixConsistency horizontal_fix_consistency_, vertical_fix_consistency_;
  // A world shift of everything placed with the position (a map fix's correction).
  void shift_placed_positions(const Eigen::Vector3d& shift, int64_t from_utime);
};

}  // namespace nadir
