#pragma once
// Which records of a capture are the pipeline's own frames. A log record
// carries no sender, so a second publisher on the estimator's channels
// (nadir_hostile, a stray simulator, a misconfigured driver) is told apart by
// what the pipeline did with its records, not by repeating the nodes' checks:
// - a frame is a CAMERA_IMAGE the tracker answered: it publishes one TRACKS
//   per image it accepts, with that image's utime and frame_counter;
// - a TRACKS is the tracker's when it answers a captured frame;
// - a VO_DELTA is the solver's when it joins two frames the tracker answered
//   (or answers a first frame: prev_utime 0).
// A stage is judged by the one before it only when the log holds that one (a
// log without TRACKS counts every decodable image as a frame). Only these
// records are counted and enter the stage and after-image latencies.

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "nadir/vo_delta_t.hpp"

namespace nadir {

struct PipelineCounts {
  int64_t frames = 0;             // images the tracker answered
  int64_t tracks = 0;             // TRACKS answering a frame
  int64_t vo_deltas = 0;          // VO_DELTA joining two frames
  int64_t vo_deltas_flagged = 0;  // of those, with a quality flag
  // Records on those channels that are none of the above (undecodable ones
  // included): a second publisher's, or images the tracker dropped.
  int64_t other_images = 0, other_tracks = 0, other_vo_deltas = 0;
};

class PipelineRecords {
 public:
  // In log order; `logged_us` is the record's log timestamp.
  void add_image(int64_t utime, int64_t frame_counter, int64_t logged_us);
  void add_tracks(int64_t utime, int64_t frame_counter, int64_t logged_us);
  void add_vo_delta(const vo_delta_t& delta, int64_t logged_us);
  void add_pose(int64_t utime, int64_t logged_us);
  // A CAMERA_IMAGE, TRACKS or VO_DELTA record that does not decode: never the pipeline's.
  void add_undecodable(const std::string& channel);

  PipelineCounts counts() const;
  // The pipeline's VO_DELTA, in log order.
  std::vector<vo_delta_t> vo_deltas() const;
  // Logger receive time - sensor time, ms, per channel (CAMERA_IMAGE,
  // TRACKS, VO_DELTA, POSE) over the pipeline's records.
  std::map<std::string, std::vector<float>> stage_latency_ms() const;
  // Per POSE: logged time - its frame's CAMERA_IMAGE logged time, ms.
  std::vector<float> after_image_latency_ms() const;

 private:
  struct Record {
    int64_t utime = 0;
    int64_t frame_counter = 0;
    int64_t logged_us = 0;
    int64_t order = 0;  // position in the log
  };
  using FrameKey = std::pair<int64_t, int64_t>;  // utime, frame_counter
  bool is_frame(const Record& image) const;
  bool is_tracker_output(const Record& tracks) const;
  bool is_solver_output(const vo_delta_t& delta) const;

  std::vector<Record> images_, tracks_, poses_;
  std::vector<std::pair<vo_delta_t, int64_t>> deltas_;  // with logged time
  std::set<FrameKey> image_keys_, tracks_keys_;
  std::set<int64_t> tracks_utimes_;
  std::set<int64_t> answered_utimes_;  // utimes of TRACKS answering a captured image
  std::map<std::string, int64_t> undecodable_;  // per channel
  int64_t order_ = 0;
};

}  // namespace nadir
