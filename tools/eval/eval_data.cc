#include "tools/eval/eval_data.h"

#include <algorithm>
#include <stdexcept>

#include "common/bus.h"
#include "common/channels.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "nadir/config_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/vo_delta_t.hpp"
#include "tools/eval/pipeline_records.h"

namespace nadir {
namespace {

template <class Msg>
bool decode(const LogEvent& e, Msg* msg) {
  std::string reason;
  return decode_message(e.data, e.size, msg, &reason);
}

void read_truth(const std::string& path, int64_t shift_us, EvalData* data) {
  LogReader reader(path);
  LogEvent e;
  while (reader.next(&e)) {
    if (e.channel == channels::kGroundTruth) {
      ground_truth_t t;
      if (decode(e, &t)) {
        t.utime += shift_us;
        data->truth.push_back(t);
      }
    } else if (e.channel == channels::kIns && data->ins.size() < 100000) {
      ins_t m;
      if (decode(e, &m)) {
        m.utime += shift_us;
        data->ins.push_back(m);
      }
    }
  }
}

}  // namespace

EvalData load_eval_data(const std::string& log_path, const std::string& truth_path, int64_t truth_shift_us) {
  EvalData data;
  LogReader reader(log_path);
  LogEvent e;
  const bool truth_here = truth_path.empty() || truth_path == log_path;
  LogHoleFinder hole_finder;
  CaptureAccountant accountant;
  PipelineRecords pipeline;
  int64_t status_messages = 0, replay_status_messages = 0;
  while (reader.next(&e)) {
    hole_finder.add(e);
    accountant.add(e);
    if (e.channel == channels::kPose) {
      pose_t p;
      if (decode(e, &p)) {
        data.poses.push_back(p);
        data.pose_log_timestamps.push_back(e.timestamp);
        pipeline.add_pose(p.utime, e.timestamp);
      }
    } else if (e.channel == channels::kMapFix) {
      map_fix_t f;
      if (decode(e, &f)) data.map_fixes.push_back(f);
    } else if (e.channel == channels::kCameraImage) {
      image_t image;
      if (decode(e, &image)) pipeline.add_image(image.utime, image.frame_counter, e.timestamp);
      else pipeline.add_undecodable(e.channel);
    } else if (e.channel == channels::kCameraTrigger) {
      ++data.triggers;
    } else if (e.channel == channels::kTracks) {
      tracks_t tracks;
      if (decode(e, &tracks)) pipeline.add_tracks(tracks.utime, tracks.frame_counter, e.timestamp);
      else pipeline.add_undecodable(e.channel);
    } else if (e.channel == channels::kVoDelta) {
      vo_delta_t d;
      if (decode(e, &d)) pipeline.add_vo_delta(d, e.timestamp);
      else pipeline.add_undecodable(e.channel);
    } else if (e.channel == channels::kConfig) {
      config_t c;
      // The VO solver's camera is the one its pairs were solved with.
      if (!decode(e, &c)) continue;
      if (c.name == "import") data.imported = true;  // tools/import writes it first
      if (c.name == "vo_solver" || (c.name == "tracker" && data.estimator_config_name.empty())) {
        data.estimator_config_yaml = c.yaml;
        data.estimator_config_name = c.name;
      }
    } else if (e.channel == channels::kStatus) {
      status_t s;
      if (decode(e, &s)) {
        ++status_messages;
        if (s.pid == 0) ++replay_status_messages;  // common/replay.cc: pid 0, no latency
        data.last_status[s.name] = s;
        if (s.latency_max_ms > 0.f) {
          data.publish_p50_ms[s.name].push_back(s.latency_p50_ms);
          data.publish_p99_ms[s.name].push_back(s.latency_p99_ms);
        }
      }
    } else if (truth_here && e.channel == channels::kGroundTruth) {
      ground_truth_t t;
      if (decode(e, &t)) data.truth.push_back(t);
    } else if (truth_here && e.channel == channels::kIns && data.ins.size() < 100000) {
      ins_t m;
      if (decode(e, &m)) data.ins.push_back(m);
    }
  }
  data.corrupt_records = reader.corrupt_records();
  data.truncated = reader.truncated();
  data.damage_report = reader.damage_report();
  data.holes = hole_finder.holes();
  data.photo_intervals = hole_finder.irregular_channels();
  data.lockstep_replay = status_messages > 0 && replay_status_messages == status_messages;
  data.accounting = accountant.result();
  data.pipeline = pipeline.counts();
  data.deltas = pipeline.vo_deltas();
  data.stage_latency_ms = pipeline.stage_latency_ms();
  data.after_image_latency_ms = pipeline.after_image_latency_ms();
  if (!truth_here) read_truth(truth_path, truth_shift_us, &data);
  if (data.poses.empty()) throw std::runtime_error(log_path + ": no POSE messages (run the estimator first)");
  if (data.truth.size() < 2) {
    throw std::runtime_error((truth_here ? log_path : truth_path) +
                             ": no GROUND_TRUTH messages (only simulated flights have truth; pass --truth)");
  }
  // Keep log order for the pose/timestamp pairing but evaluate in sensor time.
  std::vector<size_t> order(data.poses.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return data.poses[a].utime < data.poses[b].utime; });
  std::vector<pose_t> poses;
  std::vector<int64_t> stamps;
  for (size_t i : order) {
    poses.push_back(data.poses[i]);
    stamps.push_back(data.pose_log_timestamps[i]);
  }
  data.poses = std::move(poses);
  data.pose_log_timestamps = std::move(stamps);
  std::stable_sort(data.truth.begin(), data.truth.end(),
                   [](const ground_truth_t& a, const ground_truth_t& b) { return a.utime < b.utime; });
  return data;
}

}  // namespace nadir
