// The node over a real LCM bus (memq://): synchronisation by sensor time,
// identical VO_DELTA whatever the arrival order, flagged results for a stale
// altimeter and a missing INS.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "common/channels.h"
#include "common/config.h"
#include "common/geometry.h"
#include "common/lcm_bus.h"
#include "common/replay.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/vo_delta_t.hpp"
#include "processes/vo_solver/plane_model.h"
#include "processes/vo_solver/vo_solver_node.h"
#include "processes/yaw_fusion/yaw_fusion_options.h"
#include "tests/processes/vo_solver/synthetic_scene.h"

namespace nadir {
namespace {

const char* kConfig = R"(
camera: {width: 612, height: 512, fx: 398.79, fy: 398.79, cx: 305.5, cy: 255.5, mount_rpy_deg: [0, 0, 0]}
altimeter: {beam_body: [0, 0, 1]}
vo_solver:
  variant: paper
  # interpolate: waits for the range after each frame, so channels may lag
  # each other by up to altimeter_wait_ms (the arrival-order tests need it).
  sync: {altimeter_mode: interpolate, altimeter_staleness_ms: 200, altimeter_wait_ms: 300, max_pending_frames: 8}
)";

// kConfig with the attitude propagated from the INS samples at or before each
// frame (vo_solver.sync.attitude_policy: propagate) instead of interpolated.
std::string propagate_config() {
  std::string yaml = kConfig;
  const std::string sync = "sync: {";
  return yaml.insert(yaml.find(sync) + sync.size(), "attitude_policy: propagate, ");
}

constexpr int64_t kStart = 1700000000000000;
constexpr int64_t kFramePeriod = 71429;  // 14 Hz

// Smooth true attitude, so that 100 Hz samples interpolate to it closely.
double roll_at(int64_t t) { return 0.03 * std::sin(1e-6 * (t - kStart)); }
double pitch_at(int64_t t) { return -0.02 + 0.01 * std::cos(0.7e-6 * (t - kStart)); }
double yaw_at(int64_t t) { return 0.4 + 0.05e-6 * (t - kStart); }

struct Event {
  int64_t arrival;  // when it reaches the node (sensor time + transport delay)
  std::string channel;
  std::vector<uint8_t> bytes;
};

template <class Msg>
Event encode(int64_t arrival, const std::string& channel, const Msg& msg) {
  Event e{arrival, channel, std::vector<uint8_t>(msg.getEncodedSize())};
  msg.encode(e.bytes.data(), 0, static_cast<int>(e.bytes.size()));
  return e;
}

struct Sequence {
  std::vector<Event> events;
  std::map<int64_t, Eigen::Vector3d> truth;  // translation per curr frame utime
};

// TRACKS of frame k at t (612x512) whose previous frame was at `prev` (none for k = 0).
tracks_t tracks_header(int k, int64_t t, int64_t prev) {
  tracks_t m{};
  m.utime = t;
  m.prev_utime = k == 0 ? 0 : prev;
  m.frame_counter = k;
  m.width = 612;
  m.height = 512;
  m.flags = k == 0 ? tracks_t::FLAG_FIRST_FRAME : 0;
  return m;
}

// The scene's matches as TRACKS (normalized coordinates only).
void add_tracks(const vo::testing::Scene& scene, tracks_t* m) {
  m->num_tracks = static_cast<int32_t>(scene.pair.prev_norm.size());
  for (int i = 0; i < m->num_tracks; ++i) {
    m->track_id.push_back(i);
    m->age.push_back(1);
    m->prev_px.push_back({0.f, 0.f});
    m->curr_px.push_back({0.f, 0.f});
    m->prev_norm.push_back({scene.pair.prev_norm[i].x(), scene.pair.prev_norm[i].y()});
    m->curr_norm.push_back({scene.pair.curr_norm[i].x(), scene.pair.curr_norm[i].y()});
  }
}

// `frames` frames over level ground at 200 m, INS at 100 Hz, altimeter at
// 20 Hz until `altimeter_until` (sensor time).
Sequence make_sequence(int frames, int64_t altimeter_until) {
  Sequence seq;
  const int64_t end = kStart + frames * kFramePeriod + 1000000;
  for (int64_t t = kStart - 100000; t <= end; t += 10000) {
    ins_t m{};
    m.utime = t;
    m.roll = roll_at(t);
    m.pitch = pitch_at(t);
    m.yaw = yaw_at(t);
    seq.events.push_back(encode(t + 3000, channels::kIns, m));
  }
  for (int64_t t = kStart - 100000; t <= std::min(end, altimeter_until); t += 50000) {
    altimeter_t m{};
    m.utime = t;
    m.range_m = 200.0 / (std::cos(roll_at(t)) * std::cos(pitch_at(t)));  // level ground, beam along body z
    m.beam_body[2] = 1.0;
    m.signal_quality = 1.0f;
    m.validity = altimeter_t::VALID_OK;
    seq.events.push_back(encode(t + 8000, channels::kAltimeter, m));
  }
  const Eigen::Vector3d velocity_world(20.0, 5.0, 0.0);
  for (int k = 0; k < frames; ++k) {
    const int64_t t = kStart + k * kFramePeriod, tp = t - kFramePeriod;
    tracks_t m = tracks_header(k, t, tp);
    if (k > 0) {
      vo::testing::SceneSpec s;
      s.height_m = 200.0;
      s.prev_roll = roll_at(tp);
      s.prev_pitch = pitch_at(tp);
      s.prev_yaw = yaw_at(tp);
      s.curr_roll = roll_at(t);
      s.curr_pitch = pitch_at(t);
      s.curr_yaw = yaw_at(t);
      s.translation = vo::rot_z(yaw_at(tp)).transpose() * velocity_world * (kFramePeriod * 1e-6);
      s.num_features = 120;
      s.noise_px = 0.3;
      s.outlier_fraction = 0.1;
      s.seed = static_cast<uint32_t>(k);
      const vo::testing::Scene scene = vo::testing::make_scene(s);
      seq.truth[t] = scene.translation;
      add_tracks(scene, &m);
    }
    seq.events.push_back(encode(t + 40000, channels::kTracks, m));  // tracker latency
  }
  return seq;
}

// Runs the node on a memq:// LcmBus, delivering events in the given order;
// returns the encoded VO_DELTA messages by utime.
struct RunResult {
  std::map<int64_t, std::vector<uint8_t>> encoded;
  std::map<int64_t, vo_delta_t> deltas;
  StatusReport status;
};

RunResult run(const std::vector<Event>& events, const std::string& yaml = kConfig) {
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  const Config config = Config::parse(yaml, "node test");
  std::unique_ptr<Node> node = make_vo_solver_node(config, bus);
  RunResult result;
  bus.subscribe<vo_delta_t>(channels::kVoDelta, [&](const vo_delta_t& m) {
    std::vector<uint8_t> bytes(m.getEncodedSize());
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    EXPECT_EQ(result.encoded.count(m.utime), 0u) << "one VO_DELTA per frame";
    result.encoded[m.utime] = bytes;
    result.deltas[m.utime] = m;
  });
  for (const Event& e : events) {
    bus.publish_raw(e.channel, e.bytes.data(), e.bytes.size());
    while (bus.handle(0) > 0) {
    }
  }
  while (bus.handle(10) > 0) {
  }
  result.status = node->status();
  return result;
}

std::vector<Event> in_arrival_order(std::vector<Event> events) {
  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.arrival < b.arrival; });
  return events;
}

// Each channel keeps its order, but the channels are skewed against each other
// by up to +-250 ms of random extra delay per message.
std::vector<Event> interleaved(std::vector<Event> events, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int64_t> jitter(0, 250000);
  for (Event& e : events) e.arrival += jitter(rng);
  // Restore per-channel order: arrival never earlier than the previous message of the channel.
  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.arrival < b.arrival; });
  std::map<std::string, std::vector<Event*>> by_channel;
  for (Event& e : events) by_channel[e.channel].push_back(&e);
  std::vector<Event> out;
  for (auto& [channel, list] : by_channel) {
    std::vector<int64_t> arrivals;
    for (Event* e : list) arrivals.push_back(e->arrival);
    std::vector<Event*> sorted(list);
    // The channel's messages in sensor order get the channel's arrival slots in order.
    std::stable_sort(sorted.begin(), sorted.end(), [](const Event* a, const Event* b) {
      int64_t ua = 0, ub = 0;
      encoded_utime(a->bytes.data(), a->bytes.size(), &ua);
      encoded_utime(b->bytes.data(), b->bytes.size(), &ub);
      return ua < ub;
    });
    for (size_t i = 0; i < sorted.size(); ++i) {
      Event copy = *sorted[i];
      copy.arrival = arrivals[i];
      out.push_back(copy);
    }
  }
  return in_arrival_order(out);
}

TEST(VoSolverNode, EstimatesMotionFromLiveMessages) {
  const Sequence seq = make_sequence(40, INT64_MAX);
  const RunResult r = run(in_arrival_order(seq.events));
  ASSERT_EQ(r.deltas.size(), 40u);
  EXPECT_TRUE(r.deltas.begin()->second.quality & vo_delta_t::QUALITY_TOO_FEW_FEATURES) << "first frame has no pair";
  for (const auto& [utime, d] : r.deltas) {
    if (utime == kStart) continue;
    SCOPED_TRACE(utime);
    EXPECT_EQ(d.quality, 0);
    EXPECT_EQ(d.variant, "paper");
    EXPECT_EQ(d.prev_utime, utime - kFramePeriod);
    const Eigen::Vector3d& t = seq.truth.at(utime);
    EXPECT_NEAR(d.dx, t.x(), 0.1);
    EXPECT_NEAR(d.dy, t.y(), 0.1);
    EXPECT_NEAR(d.dyaw, 0.05 * kFramePeriod * 1e-6, 1e-3);
    // Height of the prev camera over the fitted patch: the patch tilt (a few
    // degrees of noise at this baseline) times the ~5 m from the altimeter spot.
    EXPECT_NEAR(d.altitude_m, 200.0, 2.0);
    EXPECT_GE(d.inliers, 90);
    EXPECT_GT(d.covariance[0][0], 0.0);
  }
  EXPECT_EQ(r.status.published, 40);
  EXPECT_EQ(r.status.dropped, 0);
}

TEST(VoSolverNode, FeatureDepthStatusCountsThePairsSolvedWithoutOwnDepths) {
  // Every frame's tracks here are a fresh scene under the same ids: no track
  // is a point seen twice, so no own depth ever forms and every pair is the
  // paper's own solve, which STATUS counts (and no pair carried a scale).
  std::string yaml = kConfig;
  yaml.replace(yaml.find("variant: paper"), std::string("variant: paper").size(), "variant: feature_depth");
  const RunResult r = run(in_arrival_order(make_sequence(20, INT64_MAX).events), yaml);
  ASSERT_EQ(r.deltas.size(), 20u);
  std::map<std::string, double> counters(r.status.counters.begin(), r.status.counters.end());
  ASSERT_EQ(counters.count("pairs_paper_alone"), 1u);
  ASSERT_EQ(counters.count("pairs_scale_carried"), 1u);
  EXPECT_EQ(counters["pairs_paper_alone"], 19);  // the first frame has no pair
  EXPECT_EQ(counters["pairs_scale_carried"], 0);
  for (const auto& [utime, d] : r.deltas) {
    if (utime == kStart) continue;
    EXPECT_EQ(d.variant, "feature_depth");
  }
}

TEST(VoSolverNode, ArrivalOrderDoesNotChangeTheOutput) {
  const Sequence seq = make_sequence(30, INT64_MAX);
  for (const std::string& yaml : {std::string(kConfig), propagate_config()}) {
    SCOPED_TRACE(yaml);
    const RunResult reference = run(in_arrival_order(seq.events), yaml);
    ASSERT_EQ(reference.encoded.size(), 30u);
    for (uint32_t seed = 1; seed <= 3; ++seed) {
      const std::vector<Event> shuffled = interleaved(seq.events, seed);
      std::string order_a, order_b;
      for (const Event& e : in_arrival_order(seq.events)) order_a += e.channel[0];
      for (const Event& e : shuffled) order_b += e.channel[0];
      ASSERT_NE(order_a, order_b) << "the channels must really be interleaved differently";
      const RunResult other = run(shuffled, yaml);
      ASSERT_EQ(other.encoded.size(), reference.encoded.size()) << "seed " << seed;
      for (const auto& [utime, bytes] : reference.encoded) {
        EXPECT_EQ(other.encoded.at(utime), bytes) << "seed " << seed << " frame " << utime;
      }
    }
  }
}

TEST(VoSolverNode, PropagateAndInterpolateAgreeWithinThePropagationError) {
  // Gently oscillating roll/pitch and a steady yaw rate, INS without rates
  // (the rate comes from the last two samples): the attitudes differ by a few
  // microradians, i.e. about a millimetre at 200 m.
  const Sequence seq = make_sequence(20, INT64_MAX);
  const RunResult interpolated = run(in_arrival_order(seq.events));
  const RunResult propagated = run(in_arrival_order(seq.events), propagate_config());
  ASSERT_EQ(propagated.deltas.size(), interpolated.deltas.size());
  for (const auto& [utime, d] : propagated.deltas) {
    const vo_delta_t& i = interpolated.deltas.at(utime);
    EXPECT_EQ(d.quality, i.quality) << utime;
    EXPECT_NEAR(d.dx, i.dx, 1e-3) << utime;
    EXPECT_NEAR(d.dy, i.dy, 1e-3) << utime;
    EXPECT_NEAR(d.dyaw, i.dyaw, 1e-6) << utime;
  }
}

TEST(VoSolverNode, FullyShuffledChannelsAreHandledWithSettleTime) {
  // Even INS samples out of order among themselves: settle_ms covers it.
  const Sequence seq = make_sequence(20, INT64_MAX);
  const std::string settled = R"(
camera: {width: 612, height: 512, fx: 398.79, fy: 398.79, cx: 305.5, cy: 255.5}
vo_solver:
  sync: {settle_ms: 400, max_pending_frames: 32}
)";
  const RunResult reference = run(in_arrival_order(seq.events), settled);
  std::vector<Event> shuffled = seq.events;
  std::mt19937 rng(11);
  std::uniform_int_distribution<int64_t> jitter(0, 250000);
  for (Event& e : shuffled) e.arrival += jitter(rng);
  const RunResult other = run(in_arrival_order(shuffled), settled);
  ASSERT_EQ(reference.encoded.size(), 20u);
  EXPECT_EQ(other.encoded, reference.encoded);
}

TEST(VoSolverNode, StaleAltimeterIsFlagged) {
  const int64_t altimeter_stops = kStart + 10 * kFramePeriod;
  const Sequence seq = make_sequence(25, altimeter_stops);
  const RunResult r = run(in_arrival_order(seq.events));
  ASSERT_EQ(r.deltas.size(), 25u);
  int stale = 0;
  for (const auto& [utime, d] : r.deltas) {
    const bool should_be_stale = utime > altimeter_stops + 200000;
    EXPECT_EQ((d.quality & vo_delta_t::QUALITY_STALE_ALTIMETER) != 0, should_be_stale) << utime;
    stale += should_be_stale;
  }
  EXPECT_GT(stale, 5);
}

TEST(VoSolverNode, MissingInsGivesFlaggedMessagesAndCountsDrops) {
  const Sequence seq = make_sequence(20, INT64_MAX);
  std::vector<Event> no_ins;
  for (const Event& e : in_arrival_order(seq.events)) {
    if (e.channel != channels::kIns) no_ins.push_back(e);
  }
  const RunResult r = run(no_ins);
  // max_pending_frames = 8: the oldest 12 are flushed, each flagged, none silent.
  ASSERT_EQ(r.deltas.size(), 12u);
  for (const auto& [utime, d] : r.deltas) EXPECT_TRUE(d.quality & vo_delta_t::QUALITY_NO_ATTITUDE) << utime;
  EXPECT_EQ(r.status.dropped, 12);
  EXPECT_NE(r.status.state, status_t::STATE_OK);
}

// Building the node from `yaml` throws a ConfigError whose message holds each of `expected`.
void expect_config_error(const std::string& yaml, const std::vector<std::string>& expected) {
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  const Config bad = Config::parse(yaml, "bad.yaml");
  try {
    make_vo_solver_node(bad, bus);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    for (const std::string& part : expected) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(VoSolverNode, BadConfigNamesTheKey) {
  const std::string camera = "camera: {width: 612, height: 512, fx: 398.79, fy: 398.79, cx: 305.5, cy: 255.5}\n";
  expect_config_error(camera + "vo_solver: {variant: ransac}\n", {"vo_solver.variant"});
  expect_config_error(camera + "vo_solver: {variant: feature_depth, feature_depth: {anchor_spots: spot}}\n",
                      {"anchor_spots", "beam | track"});
  expect_config_error(camera + "vo_solver: {variant: feature_depth, feature_depth: {scale_carry_pairs: -1}}\n",
                      {"scale_carry_pairs"});
  expect_config_error(camera + "vo_solver: {variant: feature_depth, feature_depth: {scale_process_noise: 0}}\n",
                      {"scale_process_noise"});
}

void lockstep_replay_equals_live_run(const std::string& yaml);

// The node on the lockstep ReplayBus (nadir_replay's), the events in log
// (sensor time) order; the encoded VO_DELTA by utime.
std::map<int64_t, std::vector<uint8_t>> lockstep_replay(const Sequence& seq, const std::string& yaml) {
  ReplayBus bus(nullptr);
  const Config config = Config::parse(yaml, "node test");
  std::unique_ptr<Node> node = make_vo_solver_node(config, bus);
  std::map<int64_t, std::vector<uint8_t>> replayed;
  bus.subscribe_raw(channels::kVoDelta, [&](const std::string&, const uint8_t* data, size_t size) {
    int64_t utime = 0;
    EXPECT_TRUE(encoded_utime(data, size, &utime));
    replayed[utime] = std::vector<uint8_t>(data, data + size);
  });
  std::vector<Event> log_order = seq.events;
  std::stable_sort(log_order.begin(), log_order.end(), [](const Event& a, const Event& b) {
    int64_t ua = 0, ub = 0;
    encoded_utime(a.bytes.data(), a.bytes.size(), &ua);
    encoded_utime(b.bytes.data(), b.bytes.size(), &ub);
    return ua < ub;
  });
  for (const Event& e : log_order) bus.deliver(e.channel, e.bytes.data(), e.bytes.size());
  return replayed;
}

TEST(VoSolverNode, LockstepReplayEqualsLiveRun) {
  // The replay bus delivers in log (sensor) order; the live run got the
  // channels interleaved by transport delays. Same VO_DELTA bytes.
  for (const std::string& yaml : {std::string(kConfig), propagate_config()}) {
    SCOPED_TRACE(yaml);
    lockstep_replay_equals_live_run(yaml);
  }
}

void lockstep_replay_equals_live_run(const std::string& yaml) {
  const Sequence seq = make_sequence(30, INT64_MAX);
  const RunResult live = run(interleaved(seq.events, 99), yaml);
  const std::map<int64_t, std::vector<uint8_t>> replayed = lockstep_replay(seq, yaml);
  ASSERT_EQ(replayed.size(), 30u);
  EXPECT_EQ(replayed, live.encoded);
}

}  // namespace
}  // namespace nadir

namespace nadir {
namespace {

TEST(VoSolverNode, ShippedConfigBuildsTheNode) {
  const Config config = Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
  const VoSolverOptions options = VoSolverOptions::from_config(config);
  EXPECT_EQ(options.solver.variant, vo::Variant::kFeatureDepth);  // the default
  EXPECT_DOUBLE_EQ(options.solver.focal_px, 398.79);
  EXPECT_EQ(options.sync.altimeter_wait_us, 300000);
  LcmBusOptions bus_options;
  bus_options.url = "memq://";
  LcmBus bus(bus_options);
  NodeRegistry registry;
  register_vo_solver_node(registry);
  ASSERT_NE(registry.find("vo_solver"), nullptr);
  const std::unique_ptr<Node> node = (*registry.find("vo_solver"))(config, bus);
  EXPECT_EQ(node->name(), "vo_solver");
  // The default variant (feature_depth) also publishes the ground its frames saw.
  EXPECT_EQ(node->output_channels(), (std::vector<std::string>{channels::kVoDelta, channels::kVoGround}));
}

}  // namespace
}  // namespace nadir

namespace nadir {
namespace {

TEST(VoSolverNode, NoAltimeterAndFrameGapAreFlagged) {
  // No altimeter at all: every frame waits altimeter_wait_ms of INS time,
  // then comes out flagged with no estimate.
  const Sequence silent = make_sequence(10, kStart - 1000000);
  const RunResult no_range = run(in_arrival_order(silent.events));
  ASSERT_EQ(no_range.deltas.size(), 10u);
  for (const auto& [utime, d] : no_range.deltas) {
    if (utime == kStart) continue;
    EXPECT_TRUE(d.quality & vo_delta_t::QUALITY_NO_ALTIMETER) << utime;
    EXPECT_EQ(d.dx, 0.0);
    EXPECT_EQ(d.inliers, 0);
  }
  // The tracker reports a dropped frame before frame 5: flagged, still estimated.
  Sequence seq = make_sequence(10, INT64_MAX);
  const int64_t gap_frame = kStart + 5 * kFramePeriod;
  for (Event& e : seq.events) {
    if (e.channel != channels::kTracks) continue;
    tracks_t m;
    ASSERT_EQ(m.decode(e.bytes.data(), 0, static_cast<int>(e.bytes.size())), static_cast<int>(e.bytes.size()));
    if (m.utime != gap_frame) continue;
    m.flags |= tracks_t::FLAG_FRAME_GAP;
    e = encode(e.arrival, e.channel, m);
  }
  const RunResult r = run(in_arrival_order(seq.events));
  ASSERT_EQ(r.deltas.size(), 10u);
  for (const auto& [utime, d] : r.deltas) {
    if (utime == kStart) continue;
    EXPECT_EQ(d.quality, utime == gap_frame ? vo_delta_t::QUALITY_FRAME_GAP : 0) << utime;
    EXPECT_NEAR(d.dx, seq.truth.at(utime).x(), 0.1);
  }
}

}  // namespace
}  // namespace nadir

namespace nadir {
namespace {

// A photo survey through the node: one photo every 5 s, INS samples at the
// photo's attitude 1 ms before and after it, the altimeter 1 ms before it (as
// nadir_import publishes them), a half turn between photos 3 and 4 and a
// quarter turn between 6 and 7. The config carries what an importer sets for
// such a stream (frame interval, input_checks time limits).
const char* kSurveyConfig = R"(
camera: {width: 612, height: 512, fx: 398.79, fy: 398.79, cx: 305.5, cy: 255.5, mount_rpy_deg: [0, 0, 0]}
altimeter: {beam_body: [0, 0, 1]}
input_checks: {max_ahead_s: 30, max_behind_s: 30}
vo_solver:
  variant: paper
  sync: {max_frame_interval_ms: 20000}
)";

constexpr int64_t kPhotoPeriod = 5000000;

double survey_yaw(int k) { return wrap_angle(deg_to_rad(30.0) + (k >= 4 ? M_PI : 0.0) + (k >= 7 ? -M_PI_2 : 0.0)); }
// Photos saved rotated by `rotation` (rad): the image turned about the
// camera's axis, the INS (the photo's recorded attitude) not.
double image_yaw(int k, const std::set<int>& rotated, double rotation) {
  return wrap_angle(survey_yaw(k) + (rotated.count(k) ? rotation : 0.0));
}
double survey_roll(int k) { return deg_to_rad(2.0 * std::sin(k)); }
double survey_pitch(int k) { return deg_to_rad(-1.5 * std::cos(0.7 * k)); }

Sequence make_survey(int photos, const std::set<int>& rotated = {}, double rotation = M_PI) {
  Sequence seq;
  for (int k = 0; k < photos; ++k) {
    const int64_t t = kStart + k * kPhotoPeriod;
    for (int64_t dt : {-1000, 1000}) {
      ins_t m{};
      m.utime = t + dt;
      m.roll = survey_roll(k);
      m.pitch = survey_pitch(k);
      m.yaw = survey_yaw(k);
      seq.events.push_back(encode(m.utime + 100, channels::kIns, m));
    }
    altimeter_t a{};
    a.utime = t - 1000;
    a.range_m = 60.0 / (std::cos(survey_roll(k)) * std::cos(survey_pitch(k)));
    a.beam_body[2] = 1.0;
    a.signal_quality = 1.0f;
    a.validity = altimeter_t::VALID_OK;
    seq.events.push_back(encode(a.utime + 100, channels::kAltimeter, a));
    tracks_t m = tracks_header(k, t, t - kPhotoPeriod);
    if (k > 0) {
      vo::testing::SceneSpec s;
      s.height_m = 60.0;
      s.prev_roll = survey_roll(k - 1);
      s.prev_pitch = survey_pitch(k - 1);
      s.prev_yaw = image_yaw(k - 1, rotated, rotation);
      s.curr_roll = survey_roll(k);
      s.curr_pitch = survey_pitch(k);
      s.curr_yaw = image_yaw(k, rotated, rotation);
      // 12 m along the previous heading, 3 m to its right.
      s.translation = Eigen::Vector3d(12.0, 3.0, 0.0);
      s.num_features = 80;
      s.seed = static_cast<uint32_t>(k);
      const vo::testing::Scene scene = vo::testing::make_scene(s);
      seq.truth[t] = scene.translation;
      add_tracks(scene, &m);
    }
    seq.events.push_back(encode(t + 300000, channels::kTracks, m));  // descriptor matching takes a while
  }
  return seq;
}

TEST(VoSolverNode, PhotoSurveyWithHalfTurnsBetweenPhotos) {
  const int photos = 10;
  const Sequence seq = make_survey(photos);
  const RunResult live = run(in_arrival_order(seq.events), kSurveyConfig);
  ASSERT_EQ(live.deltas.size(), static_cast<size_t>(photos));
  for (const auto& [utime, d] : live.deltas) {
    if (utime == kStart) continue;
    const int k = static_cast<int>((utime - kStart) / kPhotoPeriod);
    SCOPED_TRACE("photo " + std::to_string(k));
    EXPECT_EQ(d.quality, 0);
    const Eigen::Vector3d& t = seq.truth.at(utime);
    EXPECT_NEAR(d.dx, t.x(), 1e-6 * t.norm());
    EXPECT_NEAR(d.dy, t.y(), 1e-6 * t.norm());
    EXPECT_NEAR(d.dz, t.z(), 1e-6 * t.norm());
    EXPECT_NEAR(angle_difference(d.dyaw, angle_difference(survey_yaw(k), survey_yaw(k - 1))), 0.0, 1e-6);
  }
  EXPECT_NEAR(std::abs(live.deltas.at(kStart + 4 * kPhotoPeriod).dyaw), M_PI, 1e-6);
  EXPECT_EQ(live.status.dropped, 0);

  // The lockstep replay bus (nadir_replay's) gives the same bytes.
  const std::map<int64_t, std::vector<uint8_t>> replayed = lockstep_replay(seq, kSurveyConfig);
  EXPECT_EQ(replayed, live.encoded);
}

TEST(VoSolverNode, PhotoSavedRotatedContradictsTheInsHeading) {
  // Photo 5 saved rotated: both its pairs are not a good solve. Rotated by
  // 60 deg the fit converges to the images' heading change, 60 deg from the
  // INS's: flagged QUALITY_HEADING_CONTRADICTS. Every other pair (half and
  // quarter turns included) is not flagged.
  const int photos = 10;
  const int32_t reject_mask = YawFusionOptions{}.reject_quality_mask;
  for (double rotation_deg : {60.0, -90.0, 180.0}) {
    SCOPED_TRACE("rotated " + std::to_string(rotation_deg) + " deg");
    const RunResult r =
        run(in_arrival_order(make_survey(photos, {5}, deg_to_rad(rotation_deg)).events), kSurveyConfig);
    ASSERT_EQ(r.deltas.size(), static_cast<size_t>(photos));
    for (const auto& [utime, d] : r.deltas) {
      if (utime == kStart) continue;
      const int k = static_cast<int>((utime - kStart) / kPhotoPeriod);
      SCOPED_TRACE("photo " + std::to_string(k) + ", quality " + std::to_string(d.quality));
      if (k == 5 || k == 6) {
        EXPECT_TRUE(d.quality & reject_mask) << "published as a good solve";
        if (!(d.quality & vo_delta_t::QUALITY_NOT_CONVERGED)) {
          EXPECT_TRUE(d.quality & vo_delta_t::QUALITY_HEADING_CONTRADICTS);
        }
      } else {
        EXPECT_EQ(d.quality, 0);
      }
    }
  }
  const RunResult r = run(in_arrival_order(make_survey(photos, {5}, deg_to_rad(60.0)).events), kSurveyConfig);
  std::map<std::string, double> counters(r.status.counters.begin(), r.status.counters.end());
  EXPECT_EQ(counters["quality_heading_contradicts"], 2);

  // The bound is the option; 0 turns the check off.
  std::string off = kSurveyConfig;
  off.insert(off.find("  variant: paper"), "  max_dyaw_vs_ins_deg: 0\n");
  const RunResult unchecked = run(in_arrival_order(make_survey(photos, {5}, deg_to_rad(60.0)).events), off);
  for (const auto& [utime, d] : unchecked.deltas) EXPECT_FALSE(d.quality & vo_delta_t::QUALITY_HEADING_CONTRADICTS);
}

}  // namespace
}  // namespace nadir
