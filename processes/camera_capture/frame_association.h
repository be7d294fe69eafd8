#pragma once
// Which trigger edge started which frame.
//
// Primary key: time. A triggered camera stamps each frame on its own clock at
// a fixed delay after the trigger, so (camera timestamp - edge time) is nearly
// constant (it moves only by clock drift). Once that offset is locked, a frame
// belongs to the pending edge whose offset agrees within a tolerance; this
// survives late or bursty delivery (buffer underruns) because it never uses
// arrival time. Before lock (start, after a reconnect, after a counter
// reset), the frame's host arrival time must see exactly one edge in the
// window [arrival - max_latency, arrival - min_latency]; the match locks the
// offset. Sequence (edge sequence - frame counter) is checked on each match
// and a change is counted as a slip: it reveals missing or extra edges.
//
// Faults: a spurious or double edge (closer than min_edge_interval to the
// last accepted edge, or going back in time) is flagged and never matched; a
// missing edge leaves a frame unmatched after frame_wait, timed from the
// locked offset (camera clock quality) or flagged; a dropped frame or buffer
// underrun leaves its edge unmatched (expired when a later edge matches or
// after edge_timeout) and shows as a frame counter gap; a frame counter or
// camera clock going backwards (reconnect, camera reset) drops the lock.
// Every decision increments a counter.
//
// Deterministic and clock-free: callers pass "now" on the vehicle time base.

#include <cstdint>
#include <deque>
#include <string>
#include <utility>
#include <vector>

#include "common/config.h"
#include "processes/camera_capture/trigger_source.h"

namespace nadir {

struct AssociationOptions {
  double min_latency_us = 0;          // trigger edge -> earliest frame arrival
  double max_latency_us = 60000;      // trigger edge -> latest arrival while unlocked
  double offset_tolerance_us = 2000;  // |camera-edge offset - locked offset| to match
  double min_edge_interval_us = 5000; // closer edges are spurious (bounce, double)
  double frame_wait_us = 30000;       // how long a frame waits for its edge
  double edge_timeout_us = 1000000;   // an edge with no frame after this is dropped
  int relock_after_misses = 3;        // consecutive unmatched frames that drop the lock
  size_t max_pending_edges = 64;
  size_t max_pending_frames = 16;

  static AssociationOptions FromConfig(const Config& section);
  void Check() const;
};

struct FrameStamp {
  uint64_t token = 0;        // caller's handle for the frame (e.g. buffer slot)
  int64_t frame_counter = 0; // camera frame id
  int64_t camera_us = 0;     // camera clock timestamp (device time)
  int64_t arrival_us = 0;    // host arrival on the vehicle time base
};

enum class AssociationResult {
  kMatched,            // edge found; time from the edge
  kEstimatedFromLock,  // no edge; edge time estimated from the locked offset
  kUnmatched,          // no edge and no lock: no trigger time available
};

struct AssociationDecision {
  FrameStamp frame;
  AssociationResult result = AssociationResult::kUnmatched;
  TriggerEdge edge;            // valid for kMatched
  int64_t edge_estimate_us = 0;  // vehicle time of the (possibly estimated) edge
};

struct AssociationCounters {
  int64_t edges = 0;
  int64_t edges_spurious = 0;
  int64_t edges_without_frame = 0;   // dropped frames, underruns, or stray edges
  int64_t frames = 0;
  int64_t frames_matched = 0;
  int64_t frames_estimated = 0;      // missing edge, timed from the locked offset
  int64_t frames_unmatched = 0;
  int64_t frames_ambiguous = 0;      // several edges in the unlocked window
  int64_t frame_counter_gaps = 0;    // frames the camera counted but we never got
  int64_t frame_counter_resets = 0;
  int64_t sequence_slips = 0;
  int64_t locks = 0;                 // times the offset was (re)acquired
  int64_t lock_losses = 0;
  int64_t pending_overflow = 0;

  std::vector<std::pair<std::string, double>> as_list() const;
};

class FrameAssociator {
 public:
  explicit FrameAssociator(const AssociationOptions& options);

  // Returns false when the edge is spurious (it is counted and not matched).
  bool add_edge(const TriggerEdge& edge);
  void add_frame(const FrameStamp& frame);
  // Decides every frame that can be decided at `now_us` (vehicle time), in
  // arrival order, and expires stale edges.
  std::vector<AssociationDecision> decide(int64_t now_us);
  // Forgets the lock and the history (camera reconnected). Pending frames
  // must have been decided or are dropped by the caller.
  void reset_lock(const std::string& why);

  bool locked() const { return locked_; }
  double locked_offset_us() const { return offset_us_; }
  const AssociationCounters& counters() const { return counters_; }
  size_t pending_frames() const { return frames_.size(); }
  size_t pending_edges() const { return edges_.size(); }
  const std::string& last_lock_loss() const { return last_lock_loss_; }

 private:
  bool try_decide(const FrameStamp& frame, int64_t now_us, AssociationDecision* decision);
  // Edges in the frame's arrival window; *found = the last of them.
  int window_candidates(const FrameStamp& frame, long* found) const;
  void take_edge(size_t index, const FrameStamp& frame, AssociationDecision* decision);

  AssociationOptions options_;
  std::deque<TriggerEdge> edges_;   // accepted, unmatched, oldest first
  std::deque<FrameStamp> frames_;   // waiting for their edge, arrival order
  bool have_last_edge_ = false;
  TriggerEdge last_edge_;
  bool have_last_frame_ = false;
  FrameStamp last_frame_;
  bool locked_ = false;
  double offset_us_ = 0;            // camera_us - edge vehicle_us while locked
  bool have_sequence_offset_ = false;
  int64_t sequence_offset_ = 0;     // edge sequence - frame counter
  int misses_in_row_ = 0;
  std::string last_lock_loss_;
  AssociationCounters counters_;
};

}  // namespace nadir
