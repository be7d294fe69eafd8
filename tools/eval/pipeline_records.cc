#include "tools/eval/pipeline_records.h"

#include <iterator>

#include "common/channels.h"

namespace nadir {
namespace {

float ms_between(int64_t from_us, int64_t to_us) { return static_cast<float>((to_us - from_us) * 1e-3); }

}  // namespace

void PipelineRecords::add_image(int64_t utime, int64_t frame_counter, int64_t logged_us) {
  images_.push_back(Record{utime, frame_counter, logged_us, order_++});
  image_keys_.emplace(utime, frame_counter);
  if (tracks_keys_.count({utime, frame_counter}) != 0) answered_utimes_.insert(utime);
}

void PipelineRecords::add_tracks(int64_t utime, int64_t frame_counter, int64_t logged_us) {
  tracks_.push_back(Record{utime, frame_counter, logged_us, order_++});
  tracks_utimes_.insert(utime);
  tracks_keys_.emplace(utime, frame_counter);
  if (image_keys_.count({utime, frame_counter}) != 0) answered_utimes_.insert(utime);
}

void PipelineRecords::add_vo_delta(const vo_delta_t& delta, int64_t logged_us) { deltas_.emplace_back(delta, logged_us); }

void PipelineRecords::add_pose(int64_t utime, int64_t logged_us) { poses_.push_back(Record{utime, 0, logged_us, order_++}); }

bool PipelineRecords::is_frame(const Record& image) const {
  return tracks_.empty() || tracks_keys_.count({image.utime, image.frame_counter}) != 0;
}

bool PipelineRecords::is_tracker_output(const Record& tracks) const {
  return images_.empty() || image_keys_.count({tracks.utime, tracks.frame_counter}) != 0;
}

bool PipelineRecords::is_solver_output(const vo_delta_t& delta) const {
  if (tracks_.empty()) return true;
  // With images in the log, the frames the tracker answered; without, every TRACKS.
  const std::set<int64_t>& frames = images_.empty() ? tracks_utimes_ : answered_utimes_;
  auto known = [&](int64_t utime) { return frames.count(utime) != 0; };
  // prev_utime 0: the solver's answer to a first frame (no pair yet).
  return known(delta.utime) && (delta.prev_utime == 0 || known(delta.prev_utime));
}

void PipelineRecords::add_undecodable(const std::string& channel) { ++undecodable_[channel]; }

PipelineCounts PipelineRecords::counts() const {
  PipelineCounts c;
  auto undecodable = [&](const char* channel) {
    const auto it = undecodable_.find(channel);
    return it == undecodable_.end() ? int64_t{0} : it->second;
  };
  c.other_images = undecodable(channels::kCameraImage);
  c.other_tracks = undecodable(channels::kTracks);
  c.other_vo_deltas = undecodable(channels::kVoDelta);
  for (const Record& r : images_) (is_frame(r) ? c.frames : c.other_images) += 1;
  for (const Record& r : tracks_) (is_tracker_output(r) ? c.tracks : c.other_tracks) += 1;
  for (const auto& [d, logged] : deltas_) {
    if (!is_solver_output(d)) {
      ++c.other_vo_deltas;
      continue;
    }
    ++c.vo_deltas;
    if (d.quality != 0) ++c.vo_deltas_flagged;
  }
  return c;
}

std::vector<vo_delta_t> PipelineRecords::vo_deltas() const {
  std::vector<vo_delta_t> out;
  for (const auto& [d, logged] : deltas_) {
    if (is_solver_output(d)) out.push_back(d);
  }
  return out;
}

std::map<std::string, std::vector<float>> PipelineRecords::stage_latency_ms() const {
  std::map<std::string, std::vector<float>> out;
  for (const Record& r : images_) {
    if (is_frame(r)) out[channels::kCameraImage].push_back(ms_between(r.utime, r.logged_us));
  }
  for (const Record& r : tracks_) {
    if (is_tracker_output(r)) out[channels::kTracks].push_back(ms_between(r.utime, r.logged_us));
  }
  for (const auto& [d, logged] : deltas_) {
    if (is_solver_output(d)) out[channels::kVoDelta].push_back(ms_between(d.utime, logged));
  }
  for (const Record& r : poses_) out[channels::kPose].push_back(ms_between(r.utime, r.logged_us));
  return out;
}

std::vector<float> PipelineRecords::after_image_latency_ms() const {
  // Frames and poses merged in log order: a POSE is matched to the frame of
  // its utime logged before it, and frames before that one are done with.
  std::vector<float> out;
  std::map<int64_t, int64_t> frame_logged;  // utime -> logged time, until its POSE
  size_t i = 0;
  for (const Record& pose : poses_) {
    for (; i < images_.size() && images_[i].order < pose.order; ++i) {
      if (is_frame(images_[i])) frame_logged[images_[i].utime] = images_[i].logged_us;
    }
    const auto frame = frame_logged.find(pose.utime);
    if (frame == frame_logged.end()) continue;
    out.push_back(ms_between(frame->second, pose.logged_us));
    frame_logged.erase(frame_logged.begin(), std::next(frame));
  }
  return out;
}

}  // namespace nadir
