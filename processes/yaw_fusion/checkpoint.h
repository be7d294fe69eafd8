#pragma once
// Yaw fusion's state on disk, so a restarted process (a crash, kill -9, a
// watchdog) continues from where it was instead of restarting the position at
// zero. The checkpoint is the last published POSE, LCM-encoded (pose_t holds
// everything the filter needs: position, its covariance, fused yaw and its
// variance, velocity, frame count), written to a temporary file and renamed,
// so a reader never sees half a file. Live processes only: nadir_replay never
// reads or writes one (its output must depend on the input log alone).

#include <optional>
#include <string>

#include "nadir/pose_t.hpp"

namespace nadir {

class PoseCheckpoint {
 public:
  explicit PoseCheckpoint(std::string path) : path_(std::move(path)) {}

  // The saved POSE; nullopt when there is none. A file that exists but does
  // not decode is reported in `problem` (named with its path) and not used.
  std::optional<pose_t> load(std::string* problem) const;
  // Never throws: a failed write is counted and named in last_error().
  void save(const pose_t& pose);

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
