#pragma once
// A tracker's output against the simulator's truth: for every track in a
// TRACKS message, where the exact image of its ground point lies. Two errors:
// - flow: the tracker's curr pixel minus the exact image of the ground point
//   under its prev pixel (one frame-to-frame step, what a pair's motion sees);
// - drift: the tracker's curr pixel minus the exact image of the ground point
//   under the pixel where the track started (what a track's depth sees).
// Either exact answer can also replace the tracker's, so a solver can be run
// on tracks with no tracking error (exact) or with the tracker's drift but an
// exact step (flow), separating the tracker's error from the solver's.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/camera_model.h"
#include "nadir/tracks_t.hpp"
#include "tools/track_truth/sim_scene.h"

namespace nadir::track_truth {

enum class Rewrite {
  kNone,   // compare only
  kExact,  // prev and curr of every track: the exact images of its first ground point
  kFlow,   // curr: the exact image of the ground point under the tracker's prev pixel
};

// Mean and spread of one error (pixels, x and y).
struct ErrorStats {
  int64_t count = 0;
  double mean_x = 0, mean_y = 0;
  double rms = 0;         // of the error's length
  double median_abs = 0;  // of the error's length
};

struct AgeBin {
  int from = 0, to = 0;  // track age (frames, as the tracker counts) in [from, to)
  ErrorStats drift;
  // The drift's expansion about the principal point (as the flow's, below,
  // but accumulated over the track's life): what a depth triangulated from
  // the track's first ray reads as a depth error.
  double drift_expansion = 0;
  // The one-step flow error's expansion for the tracks of these ages.
  double flow_expansion = 0;
};

struct TrackTruthReport {
  int64_t messages = 0;
  int64_t messages_without_truth = 0;  // no frame truth near prev or curr: not compared
  int64_t tracks = 0;                  // in the compared messages
  int64_t ray_misses = 0;              // a prev pixel whose ray misses the ground
  int64_t occluded = 0;                // ground point hidden from curr: not in the statistics
  ErrorStats flow;
  // The flow error's expansion about the principal point: k of the least
  // squares fit error = shift + k * (curr pixel - principal point), per frame
  // (a common shift of all tracks kept apart). A spurious
  // expansion is what a solver reads as vertical motion (about -k * height a
  // frame), so this is the tracker's vertical walk in one number.
  double flow_expansion_per_frame = 0;
  std::vector<AgeBin> drift_by_age;
};

// Least squares fit of error = shift + k * radius over many tracks: k, the
// expansion about the principal point (a common shift kept apart).
class ExpansionFit {
 public:
  void add(const Eigen::Vector2d& error, const Eigen::Vector2d& radius);
  int64_t count() const { return count_; }
  // 0 with fewer than three tracks.
  double expansion() const;

 private:
  int64_t count_ = 0;
  double sum_rx_ = 0, sum_ry_ = 0, sum_rr_ = 0, sum_ex_ = 0, sum_ey_ = 0, sum_er_ = 0;
};

// One TRACKS message's flow error (pixels).
struct FrameFlow {
  int64_t utime = 0;
  int64_t count = 0;  // tracks compared
  double mean_x = 0, mean_y = 0, rms = 0;
  double expansion = 0;  // per frame, as TrackTruthReport::flow_expansion_per_frame
};

class TrackTruth {
 public:
  // `estimator_camera`: the camera model that turned the tracker's pixels
  // into its normalized coordinates (tracker config), used to write the
  // rewritten ones the same way.
  TrackTruth(const SimScene& scene, const CameraModel& estimator_camera);

  // Compares one message; with a rewrite, replaces its positions (pixels and
  // normalized) where the truth has them and leaves the rest as tracked.
  // Returns the message's own flow error (count 0: not compared).
  FrameFlow process(tracks_t* tracks, Rewrite rewrite);
  TrackTruthReport report() const;

 private:
  struct Accumulator {
    int64_t count = 0;
    double sum_x = 0, sum_y = 0, sum_sq = 0;
    std::vector<float> lengths;
    void add(const Eigen::Vector2d& e);
    ErrorStats stats();
  };
  // Pixel `px` and its normalized coordinates (the estimator's camera) into
  // one end of a track: pixel[2], normalized[2].
  void write_position(const Eigen::Vector2d& px, float* pixel, double* normalized) const;

  const SimScene& scene_;
  CameraModel estimator_camera_;
  TrackTruthReport counts_;
  Accumulator flow_;
  ExpansionFit expansion_;
  std::vector<Accumulator> drift_;
  std::vector<ExpansionFit> drift_expansion_;
  std::vector<ExpansionFit> flow_expansion_by_age_;
  std::unordered_map<int64_t, Eigen::Vector3d> first_point_;  // track id -> ground point where it started
  std::unordered_map<int64_t, int64_t> last_seen_;            // track id -> message index
};

// Age bins of the drift: [1,5), [5,10), [10,20), ... [160,320), [320, inf).
const std::vector<std::array<int, 2>>& drift_age_bins();

}  // namespace nadir::track_truth
