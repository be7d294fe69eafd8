#pragma once
// What an evaluation needs from a log: estimates, truth and bookkeeping.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/capture_accounting.h"
#include "common/log_holes.h"
#include "tools/eval/pipeline_records.h"
#include "nadir/ground_truth_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/map_fix_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/status_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir {

struct EvalData {
  std::vector<pose_t> poses;                // sorted by utime
  std::vector<int64_t> pose_log_timestamps; // logger receive time of each pose
  std::vector<ground_truth_t> truth;        // sorted by utime, all kinds
  std::vector<ins_t> ins;                   // first few, for the geographic reference
  std::vector<map_fix_t> map_fixes;         // the map matcher's accepted fixes, log order
  int64_t triggers = 0;
  // The pipeline's own frames, TRACKS and VO_DELTA, and the records on those
  // channels that are not (tools/eval/pipeline_records.h).
  PipelineCounts pipeline;
  std::vector<vo_delta_t> deltas;           // the pipeline's, in log order
  int64_t corrupt_records = 0;
  bool truncated = false;
  std::string damage_report;        // "FILE: byte N: what" lines
  std::vector<LogHole> holes;       // capture holes (lcm-logger stopped, buffers overflowed)
  // A photo flight's channels: their intervals, one summary each, instead of
  // holes (common/log_holes.h).
  std::vector<ChannelIntervals> photo_intervals;
  // The log holds the CONFIG nadir_import writes: an imported flight, whose
  // truth is the flight's own record (GPS, the photos' recorded attitude).
  bool imported = false;
  // Every STATUS in the log comes from nadir_replay (pid 0): a lockstep
  // replay, whose log times are the input's, not when anything was computed.
  bool lockstep_replay = false;
  CaptureAccounting accounting;     // the capture against its publishers' STATUS counts
  std::map<std::string, status_t> last_status;  // per process name
  // Per process, the publish latency (sensor time -> publish, measured by the
  // process) of every 1 s STATUS period that published anything: p50s, p99s.
  std::map<std::string, std::vector<float>> publish_p50_ms, publish_p99_ms;
  // Logger receive time - sensor time, ms, per pipeline stage (live
  // captures), over the pipeline's own records.
  std::map<std::string, std::vector<float>> stage_latency_ms;
  // Per POSE: logged time - its frame's CAMERA_IMAGE logged time (the
  // estimator and its hops, without the image source's own delay).
  std::vector<float> after_image_latency_ms;
  // The estimator's effective config as its CONFIG message gave it (the VO
  // solver's, else the tracker's): the camera of the frame-pair footprints.
  // Empty when the log has neither.
  std::string estimator_config_yaml;
  std::string estimator_config_name;
};

// Reads POSE (and STATUS, counts) from `log_path`, GROUND_TRUTH and INS from
// `truth_path` (the same file when empty). Throws std::runtime_error naming
// the file and the missing channel.
// `truth_shift_us` is added to every GROUND_TRUTH/INS utime from `truth_path`
// (a simulator log replayed on another clock, e.g. the hil set).
EvalData load_eval_data(const std::string& log_path, const std::string& truth_path, int64_t truth_shift_us = 0);

}  // namespace nadir
