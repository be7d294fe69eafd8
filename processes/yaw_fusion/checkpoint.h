#pragma once
// Yaw fusion's state on disk, so a restarted process (a crash, kill -9, a
// watchdog) continues from where it was instead of restarting the position at
// zero. The checkpoint is the last published POSE (pose_t holds what the
// filter needs: position, its covariance, fused yaw and its variance,
// velocity, frame count) and the INS heading bias as map fixes estimated it,
// LCM-encoded as a yaw_fusion_checkpoint_t, written to a temporary file and
// renamed, so a reader never sees half a file. A file holding a bare pose_t
// (as written before the bias was kept) still loads, without the bias. Live
// processes only: nadir_replay never reads or writes one (its output must
// depend on the input log alone).

#include <optional>
#include <string>

#include "nadir/pose_t.hpp"
#include "nadir/yaw_fusion_checkpoint_t.hpp"

namespace nadir {

// A checkpoint of `pose` alone (has_heading_bias false).
yaw_fusion_checkpoint_t checkpoint_without_bias(const pose_t& pose);

class PoseCheckpoint {
 public:
  explicit PoseCheckpoint(std::string path) : path_(std::move(path)) {}

  // The saved checkpoint; nullopt when there is none. A file that exists but
  // does not decode as either format is reported in `problem` (named with
  // its path) and not used.
  std::optional<yaw_fusion_checkpoint_t> load(std::string* problem) const;
  // Never throws: a failed write is counted and named in last_error().
  void save(const yaw_fusion_checkpoint_t& checkpoint);

  const std::string& path() const { return path_; }
  int64_t saves() const { return saves_; }
  int64_t save_errors() const { return save_errors_; }
  const std::string& last_error() const { return last_error_; }

 private:
  std::string path_;
  int64_t saves_ = 0;
  int64_t save_errors_ = 0;
  std::string last_error_;
};

}  // namespace nadir
