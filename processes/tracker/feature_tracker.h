#pragma once
// The tracker's algorithm without any transport: per frame, pyramidal KLT of
// the existing features from the previous frame, a forward-backward
// consistency check, then per-cell replenishment with Harris corners. Track
// ids and ages survive replenishment. The image pyramid is built once per
// frame and used for the forward pass, the backward pass and, as the previous
// pyramid, for the next frame.
//
// Deterministic: no randomness, no clock, no threads; KLT (lucas_kanade.h)
// gives the same bits on every instruction set.

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "common/camera_model.h"
#include "processes/tracker/grid_corner_detector.h"
#include "processes/tracker/lucas_kanade.h"
#include "processes/tracker/tracker_options.h"

namespace nadir {

// One feature followed from the previous frame into the current one.
struct FeatureTrack {
  int64_t id = 0;
  int32_t age = 0;  // frames this feature has been seen in (>= 2 in a track)
  cv::Point2f prev_px;
  cv::Point2f curr_px;
};

struct TrackStepResult {
  bool first_frame = false;          // no reference frame: nothing tracked
  std::vector<FeatureTrack> tracks;  // survivors, in ascending id order
  int attempted = 0;                 // features tracked forward
  int klt_lost = 0;                  // KLT failed forward or backward
  int out_of_image = 0;              // tracked to within border_px of the edge or beyond
  int fb_rejected = 0;               // forward-backward error above threshold
  int patch_rejected = 0;            // patch changed far more than the frame's typical track
  int replenished = 0;               // new corners added in this frame
  int cells_replenished = 0;         // cells that needed new corners
  int features_after = 0;            // features carried into the next frame
};

class FeatureTracker {
 public:
  // `lens`, when given, is the camera whose distortion the window warp
  // (options.klt_window_warp) accounts for; without it the warp follows the
  // image motion alone, as for an undistorted image.
  explicit FeatureTracker(const TrackerOptions& options, const CameraModel* lens = nullptr);

  // Tracks from the reference frame into `image` (CV_8UC1), replenishes, and
  // makes `image` the new reference. The first call (or after reset) only
  // detects. Throws std::invalid_argument for an image that is not 8-bit mono.
  // The same as track_frame() then prepare_next(), for callers that do not
  // publish in between.
  TrackStepResult process(const cv::Mat& image);

  // The two halves of process(), so that the tracks can go out before the
  // work that only the next frame needs. track_frame() fills everything but
  // replenished, cells_replenished and features_after, which prepare_next()
  // adds: it must follow with the same image (still valid) and result before
  // the next track_frame().
  TrackStepResult track_frame(const cv::Mat& image);
  void prepare_next(const cv::Mat& image, TrackStepResult& result);

  // Forgets the reference frame and all features (ids keep counting up).
  void reset();
  bool has_reference() const { return !prev_pyramid_.empty(); }
  // Ids are never reused; a caller that runs another tracker beside this one
  // (tracker.mode auto) shares the count through these.
  int64_t next_id() const { return next_id_; }
  void set_next_id(int64_t id) { next_id_ = id; }

  struct Feature {
    int64_t id;
    int32_t age;
    cv::Point2f px;
    // The last pair's local linear map prev -> curr around this feature,
    // fitted to its neighbours' tracks (klt_local_warp); unset for new ones.
    bool has_local_warp = false;
    cv::Matx22f local_warp = cv::Matx22f::eye();
  };
  // Features carried into the next frame (tracked survivors + new corners).
  const std::vector<Feature>& features() const { return features_; }
  const TrackerOptions& options() const { return options_; }

 private:
  void track(TrackStepResult& result);
  // Pyramid levels above full resolution whose KLT window around `p` stays
  // inside the image (0..max_level_).
  int usable_levels(const cv::Point2f& p) const;
  // Affine image motion from the tracks found so far; false when too few.
  bool fit_motion(double fb_sq, cv::Matx23d* motion) const;
  // Tracks the features in group_index_ forward with `max_level` pyramid
  // levels above full resolution, starting from `motion`'s prediction (or
  // their own position when null), and back again; stores the results.
  void track_group(int max_level, const cv::Matx23d* motion);
  // Fills warp_ / has_warp_ for the features in group_index_, predicted at
  // `predicted` (one per group member) under `motion`'s linear part.
  void window_warps(const std::vector<cv::Point2f>& predicted, const cv::Matx23d& motion);
  // Fits each survivor's local_warp to the tracks around it (prev -> curr).
  void fit_local_warps(std::vector<Feature>& survivors, const std::vector<size_t>& track_index) const;
  // Tracked, but lost by KLT or beyond the forward-backward threshold.
  bool failed(size_t i, double fb_sq) const;
  void replenish(const cv::Mat& image, TrackStepResult& result);

  TrackerOptions options_;
  GridCornerDetector detector_;
  LucasKanade forward_klt_;
  LucasKanade backward_klt_;
  int pyramid_border_;
  int max_level_;
  int fb_max_level_;
  int64_t next_id_ = 1;
  std::vector<Feature> features_;
  LkPyramid prev_pyramid_;
  LkPyramid curr_pyramid_;
  cv::Size image_size_;
  bool have_last_motion_ = false;
  cv::Matx23d last_motion_;  // affine prev -> curr of the last tracked pair
  bool has_lens_ = false;
  CameraModel lens_;

  // Window warps: per feature, the lens's inverse magnification at its prev
  // pixel, and the group's warps (prev -> curr offsets) as the KLT takes them.
  std::vector<cv::Matx22d> prev_lens_inverse_;
  std::vector<cv::Matx22f> warp_;
  std::vector<uchar> has_warp_;

  // Buffers reused between frames.
  std::vector<cv::Point2f> prev_pts_, curr_pts_, back_pts_;
  std::vector<uchar> status_fwd_, status_bwd_;
  std::vector<int> usable_level_, level_used_;  // per feature; level_used_ -1: not tracked yet
  std::vector<size_t> group_index_;
  std::vector<float> patch_error_, patch_errors_sorted_;
};

}  // namespace nadir
