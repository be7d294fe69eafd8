#include "processes/camera_capture/frame_association.h"

#include <cmath>

namespace nadir {

namespace {
// GigE Vision 1.x block ids are 16 bit and wrap; a wrap is not a reset.
bool is_counter_wrap(int64_t previous, int64_t next) { return previous >= 0xFF00 && next <= 0x00FF; }
}  // namespace

AssociationOptions AssociationOptions::FromConfig(const Config& c) {
  AssociationOptions o;
  c.require_known_keys({"min_latency_us", "max_latency_us", "offset_tolerance_us", "min_edge_interval_us",
                        "frame_wait_us", "edge_timeout_us", "relock_after_misses", "max_pending_edges",
                        "max_pending_frames"});
  o.min_latency_us = c.get<double>("min_latency_us", o.min_latency_us);
  o.max_latency_us = c.get<double>("max_latency_us", o.max_latency_us);
  o.offset_tolerance_us = c.get<double>("offset_tolerance_us", o.offset_tolerance_us);
  o.min_edge_interval_us = c.get<double>("min_edge_interval_us", o.min_edge_interval_us);
  o.frame_wait_us = c.get<double>("frame_wait_us", o.frame_wait_us);
  o.edge_timeout_us = c.get<double>("edge_timeout_us", o.edge_timeout_us);
  o.relock_after_misses = c.get<int>("relock_after_misses", o.relock_after_misses);
  o.max_pending_edges = c.get<size_t>("max_pending_edges", o.max_pending_edges);
  o.max_pending_frames = c.get<size_t>("max_pending_frames", o.max_pending_frames);
  c.check_range("min_latency_us", o.min_latency_us, 0.0, 1e6);
  c.check_range("max_latency_us", o.max_latency_us, o.min_latency_us + 1.0, 5e6);
  c.check_range("offset_tolerance_us", o.offset_tolerance_us, 1.0, 1e6);
  c.check_range("min_edge_interval_us", o.min_edge_interval_us, 0.0, 1e6);
  c.check_range("frame_wait_us", o.frame_wait_us, 0.0, 5e6);
  c.check_range("edge_timeout_us", o.edge_timeout_us, 1000.0, 60e6);
  c.check_range("relock_after_misses", o.relock_after_misses, 1, 1000);
  c.check_range<size_t>("max_pending_edges", o.max_pending_edges, 2, 10000);
  c.check_range<size_t>("max_pending_frames", o.max_pending_frames, 1, 1000);
  return o;
}

void AssociationOptions::Check() const {
  const std::string s = "camera_capture.association";
  require_option(min_latency_us >= 0, s, "min_latency_us", "must be >= 0");
  require_option(max_latency_us > min_latency_us, s, "max_latency_us", "must be > min_latency_us");
  require_option(offset_tolerance_us > 0, s, "offset_tolerance_us", "must be > 0");
  require_option(min_edge_interval_us >= 0, s, "min_edge_interval_us", "must be >= 0");
  require_option(frame_wait_us >= 0, s, "frame_wait_us", "must be >= 0");
  require_option(edge_timeout_us > 0, s, "edge_timeout_us", "must be > 0");
  require_option(relock_after_misses >= 1, s, "relock_after_misses", "must be >= 1");
  require_option(max_pending_edges >= 2, s, "max_pending_edges", "must be >= 2");
  require_option(max_pending_frames >= 1, s, "max_pending_frames", "must be >= 1");
}

std::vector<std::pair<std::string, double>> AssociationCounters::as_list() const {
  return {{"assoc_edges", double(edges)},
          {"assoc_edges_spurious", double(edges_spurious)},
          {"assoc_edges_without_frame", double(edges_without_frame)},
          {"assoc_frames", double(frames)},
          {"assoc_frames_matched", double(frames_matched)},
          {"assoc_frames_estimated", double(frames_estimated)},
          {"assoc_frames_unmatched", double(frames_unmatched)},
          {"assoc_frames_ambiguous", double(frames_ambiguous)},
          {"assoc_frame_counter_gaps", double(frame_counter_gaps)},
          {"assoc_frame_counter_resets", double(frame_counter_resets)},
          {"assoc_sequence_slips", double(sequence_slips)},
          {"assoc_locks", double(locks)},
          {"assoc_lock_losses", double(lock_losses)},
          {"assoc_pending_overflow", double(pending_overflow)}};
}

FrameAssociator::FrameAssociator(const AssociationOptions& options) : options_(options) { options_.Check(); }

bool FrameAssociator::add_edge(const TriggerEdge& edge) {
  ++counters_.edges;
  if (have_last_edge_ && static_cast<double>(edge.vehicle_us - last_edge_.vehicle_us) < options_.min_edge_interval_us) {
    ++counters_.edges_spurious;
    return false;
  }
  have_last_edge_ = true;
  last_edge_ = edge;
  edges_.push_back(edge);
  while (edges_.size() > options_.max_pending_edges) {
    edges_.pop_front();
    ++counters_.pending_overflow;
    ++counters_.edges_without_frame;
  }
  return true;
}

void FrameAssociator::add_frame(const FrameStamp& frame) {
  ++counters_.frames;
  if (have_last_frame_) {
    const int64_t previous = last_frame_.frame_counter;
    const bool clock_back = frame.camera_us != 0 && last_frame_.camera_us != 0 && frame.camera_us < last_frame_.camera_us;
    if (frame.frame_counter <= previous && !is_counter_wrap(previous, frame.frame_counter)) {
      ++counters_.frame_counter_resets;
      reset_lock("frame counter went back from " + std::to_string(previous) + " to " +
                 std::to_string(frame.frame_counter));
    } else if (clock_back) {
      ++counters_.frame_counter_resets;
      reset_lock("camera clock went backwards");
    } else if (is_counter_wrap(previous, frame.frame_counter)) {
      have_sequence_offset_ = false;  // keep the lock, restart the sequence check
    } else if (frame.frame_counter > previous + 1) {
      counters_.frame_counter_gaps += frame.frame_counter - previous - 1;
    }
  }
  have_last_frame_ = true;
  last_frame_ = frame;
  frames_.push_back(frame);
}

void FrameAssociator::reset_lock(const std::string& why) {
  if (locked_) {
    ++counters_.lock_losses;
    last_lock_loss_ = why;
  }
  locked_ = false;
  have_sequence_offset_ = false;
  misses_in_row_ = 0;
}

void FrameAssociator::take_edge(size_t index, const FrameStamp& frame, AssociationDecision* decision) {
  // Frames arrive in trigger order, so edges older than the matched one will
  // never get a frame: their frames were dropped or they were stray edges.
  counters_.edges_without_frame += static_cast<int64_t>(index);
  const TriggerEdge edge = edges_[index];
  edges_.erase(edges_.begin(), edges_.begin() + static_cast<long>(index) + 1);

  const int64_t sequence_offset = edge.sequence - frame.frame_counter;
  if (have_sequence_offset_ && sequence_offset != sequence_offset_) ++counters_.sequence_slips;
  have_sequence_offset_ = true;
  sequence_offset_ = sequence_offset;

  if (frame.camera_us != 0) {
    if (!locked_) ++counters_.locks;
    locked_ = true;
    // Follow the camera clock's drift: the newest match defines the offset.
    offset_us_ = static_cast<double>(frame.camera_us - edge.vehicle_us);
  }
  misses_in_row_ = 0;
  ++counters_.frames_matched;
  decision->result = AssociationResult::kMatched;
  decision->edge = edge;
  decision->edge_estimate_us = edge.vehicle_us;
}

int FrameAssociator::window_candidates(const FrameStamp& frame, long* found) const {
  const double latest_edge = static_cast<double>(frame.arrival_us) - options_.min_latency_us;
  const double earliest_edge = static_cast<double>(frame.arrival_us) - options_.max_latency_us;
  int candidates = 0;
  for (size_t i = 0; i < edges_.size(); ++i) {
    const double t = static_cast<double>(edges_[i].vehicle_us);
    if (t > latest_edge) break;
    if (t >= earliest_edge) {
      ++candidates;
      *found = static_cast<long>(i);
    }
  }
  return candidates;
}

bool FrameAssociator::try_decide(const FrameStamp& frame, int64_t now_us, AssociationDecision* decision) {
  decision->frame = frame;
  const bool waited = static_cast<double>(now_us - frame.arrival_us) >= options_.frame_wait_us ||
                      frames_.size() > options_.max_pending_frames;
  const double latest_edge = static_cast<double>(frame.arrival_us) - options_.min_latency_us;

  if (locked_ && frame.camera_us != 0) {
    long best = -1;
    double best_error = options_.offset_tolerance_us;
    for (size_t i = 0; i < edges_.size(); ++i) {
      if (static_cast<double>(edges_[i].vehicle_us) > latest_edge) break;
      const double error = std::fabs(static_cast<double>(frame.camera_us - edges_[i].vehicle_us) - offset_us_);
      if (error <= best_error) {
        best_error = error;
        best = static_cast<long>(i);
      }
    }
    if (best >= 0) {
      take_edge(static_cast<size_t>(best), frame, decision);
      return true;
    }
    if (!waited) return false;
    // The camera's delay may have changed (first frames after start, a mode
    // change): one unambiguous edge in the arrival window relocks.
    long found = -1;
    if (window_candidates(frame, &found) == 1) {
      reset_lock("camera-edge offset moved by " +
                 std::to_string(static_cast<int64_t>(frame.camera_us - edges_[static_cast<size_t>(found)].vehicle_us -
                                                     offset_us_)) +
                 " us");
      take_edge(static_cast<size_t>(found), frame, decision);
      return true;
    }
    // Missing edge: the camera clock and the locked offset still say when
    // the trigger happened, at camera-clock quality.
    decision->result = AssociationResult::kEstimatedFromLock;
    decision->edge_estimate_us = frame.camera_us - static_cast<int64_t>(std::llround(offset_us_));
    ++counters_.frames_estimated;
    if (++misses_in_row_ >= options_.relock_after_misses) {
      reset_lock(std::to_string(misses_in_row_) + " frames in a row without an edge at the locked offset");
    }
    return true;
  }

  // Unlocked: wait the full frame_wait so that a late-read edge is seen, then
  // accept only an unambiguous edge in the arrival window.
  if (!waited) return false;
  long found = -1;
  const int candidates = window_candidates(frame, &found);
  if (candidates == 1) {
    take_edge(static_cast<size_t>(found), frame, decision);
    return true;
  }
  if (candidates > 1) ++counters_.frames_ambiguous;
  ++misses_in_row_;
  ++counters_.frames_unmatched;
  decision->result = AssociationResult::kUnmatched;
  return true;
}

std::vector<AssociationDecision> FrameAssociator::decide(int64_t now_us) {
  std::vector<AssociationDecision> decisions;
  while (!frames_.empty()) {
    AssociationDecision decision;
    if (!try_decide(frames_.front(), now_us, &decision)) break;
    frames_.pop_front();
    decisions.push_back(decision);
  }
  while (!edges_.empty() && static_cast<double>(now_us - edges_.front().vehicle_us) > options_.edge_timeout_us) {
    edges_.pop_front();
    ++counters_.edges_without_frame;
  }
  return decisions;
}

}  // namespace nadir
