// nadir_track_truth: a tracker's TRACKS against the simulator's exact
// projections (flow and drift errors), and optionally a copy of the log with
// the tracks replaced by the exact ones.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include "common/channels.h"
#include "common/config.h"
#include "common/json_writer.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "common/paths.h"
#include "common/progress.h"
#include "nadir/config_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/tracks_t.hpp"
#include "tools/track_truth/track_truth.h"

namespace {

using nadir::track_truth::ErrorStats;
using nadir::track_truth::Rewrite;
using nadir::track_truth::TrackTruthReport;

struct Inputs {
  std::string sim_config;      // yaml of the simulator's CONFIG
  std::string tracker_config;  // yaml of the tracker's CONFIG, when the log has it
  int64_t truth_messages = 0;
};

// The simulator's and the tracker's CONFIG, from the first pass.
void read_configs(nadir::LogReader* reader, Inputs* in) {
  nadir::LogEvent e;
  while (reader->next(&e)) {
    if (e.channel != nadir::channels::kConfig) continue;
    nadir::config_t c;
    std::string why;
    if (!nadir::decode_message(e.data, e.size, &c, &why)) continue;
    if (c.name == "sim" && in->sim_config.empty()) in->sim_config = c.yaml;
    if (c.name == "tracker" && in->tracker_config.empty()) in->tracker_config = c.yaml;
  }
  reader->rewind();
}

void print_stats(const char* label, const ErrorStats& s) {
  std::printf("%-22s n %9lld  mean x %+.5f y %+.5f px  rms %.4f px  median |e| %.4f px\n", label,
              static_cast<long long>(s.count), s.mean_x, s.mean_y, s.rms, s.median_abs);
}

void write_stats(nadir::JsonWriter* j, const ErrorStats& s) {
  j->begin_object()
      .field("count", s.count)
      .field("mean_x_px", s.mean_x)
      .field("mean_y_px", s.mean_y)
      .field("rms_px", s.rms)
      .field("median_abs_px", s.median_abs)
      .end_object();
}

std::string report_json(const TrackTruthReport& r, int64_t corrupt, uint64_t seed, double relief) {
  nadir::JsonWriter j;
  j.begin_object()
      .field("seed", static_cast<int64_t>(seed))
      .field("relief_scale", relief)
      .field("messages", r.messages)
      .field("messages_without_truth", r.messages_without_truth)
      .field("tracks", r.tracks)
      .field("ray_misses", r.ray_misses)
      .field("occluded", r.occluded)
      .field("corrupt_records", corrupt);
  j.key("flow");
  write_stats(&j, r.flow);
  j.field("flow_expansion_per_frame", r.flow_expansion_per_frame);
  j.key("drift_by_age").begin_array();
  for (const auto& bin : r.drift_by_age) {
    j.begin_object().field("age_from", bin.from).field("age_to", bin.to);
    j.key("drift");
    write_stats(&j, bin.drift);
    j.field("drift_expansion", bin.drift_expansion);
    j.field("flow_expansion", bin.flow_expansion);
    j.end_object();
  }
  j.end_array().end_object();
  return j.str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Compares a log's TRACKS with the simulator's exact projections: the flow error (the tracker's curr "
      "pixel against the exact image of the ground point under its prev pixel) and the drift by track age "
      "(against the image of the ground point where the track started). With --out, writes a copy of the "
      "log whose TRACKS are the exact ones (--rewrite exact) or carry the tracker's drift with an exact "
      "step (--rewrite flow), to run the solver on tracks without the tracker's error. The world (terrain, "
      "true camera, mount) comes from the simulator's CONFIG in the log.",
      "nadir_track_truth"};
  std::string in_path, truth_path, out_path, config_path, frames_path, rewrite_name = "exact";
  bool json = false, drop_images = false;
  app.add_option("--in", in_path, "log with TRACKS (a replay of a simulated flight)")->required();
  app.add_option("--truth", truth_path, "log with GROUND_TRUTH and the simulator's CONFIG (default: --in)");
  app.add_option("--config", config_path,
                 "config whose camera turned pixels into normalized coordinates, for --out (default: the tracker's "
                 "CONFIG in --in, else <checkout>/config/default.yaml)");
  app.add_option("--out", out_path, "write a copy of --in with TRACKS rewritten");
  app.add_option("--rewrite", rewrite_name, "exact | flow (with --out)")->check(CLI::IsMember({"exact", "flow"}));
  app.add_option("--frames", frames_path,
                 "write each TRACKS message's flow error as CSV (utime, tracks, mean x/y, rms, expansion)");
  app.add_flag("--drop-images", drop_images, "leave CAMERA_IMAGE out of --out (a tenth of the size)");
  app.add_flag("--json", json, "print the report as JSON");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    nadir::LogReader reader(in_path);
    std::unique_ptr<nadir::LogReader> truth_reader;
    if (!truth_path.empty()) truth_reader = std::make_unique<nadir::LogReader>(truth_path);
    nadir::LogReader& truth = truth_reader ? *truth_reader : reader;
    Inputs in;
    read_configs(&truth, &in);
    if (truth_reader) {
      Inputs own;
      read_configs(&reader, &own);
      in.tracker_config = own.tracker_config;
    }
    if (in.sim_config.empty()) {
      std::fprintf(stderr,
                   "nadir_track_truth: error: %s: no CONFIG from nadir_sim (name 'sim'): not a simulated "
                   "flight, or the capture left it out\n",
                   truth.path().c_str());
      return 1;
    }
    nadir::track_truth::SimScene scene(in.sim_config, truth.path() + ": CONFIG sim");
    nadir::LogEvent e;
    while (truth.next(&e)) {
      if (e.channel != nadir::channels::kGroundTruth) continue;
      nadir::ground_truth_t g;
      std::string why;
      if (nadir::decode_message(e.data, e.size, &g, &why)) scene.add_truth(g);
    }
    truth.rewind();
    if (scene.frames() == 0) {
      std::fprintf(stderr, "nadir_track_truth: error: %s: no frame GROUND_TRUTH\n", truth.path().c_str());
      return 1;
    }
    nadir::CameraModel camera;
    if (!config_path.empty()) {
      camera = nadir::CameraModel::from_config(nadir::Config::load_file(config_path));
    } else if (!in.tracker_config.empty()) {
      camera = nadir::CameraModel::from_config(nadir::Config::parse(in.tracker_config, in_path + ": CONFIG tracker"));
    } else {
      camera = nadir::CameraModel::from_config(nadir::Config::load_file(nadir::default_config_path()));
    }
    const Rewrite rewrite = out_path.empty()         ? Rewrite::kNone
                            : rewrite_name == "flow" ? Rewrite::kFlow
                                                     : Rewrite::kExact;
    nadir::track_truth::TrackTruth compare(scene, camera);
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> frames(nullptr, &std::fclose);
    if (!frames_path.empty()) {
      frames.reset(std::fopen(frames_path.c_str(), "w"));
      if (!frames) throw std::runtime_error(frames_path + ": cannot create");
      std::fprintf(frames.get(), "utime,tracks,mean_x_px,mean_y_px,rms_px,expansion_per_frame\n");
    }
    std::unique_ptr<nadir::LogWriter> writer;
    if (!out_path.empty()) writer = std::make_unique<nadir::LogWriter>(out_path);
    nadir::ProgressBar progress("track truth", static_cast<double>(reader.size()),
                                !json && nadir::stderr_is_terminal());
    int64_t malformed = 0;
    while (reader.next(&e)) {
      progress.update(static_cast<double>(reader.position()));
      if (e.channel == nadir::channels::kTracks) {
        nadir::tracks_t tracks;
        std::string why;
        if (!nadir::decode_message(e.data, e.size, &tracks, &why)) {
          ++malformed;
          std::fprintf(stderr, "nadir_track_truth: warning: %s: byte %llu: TRACKS skipped: %s\n", in_path.c_str(),
                       static_cast<unsigned long long>(e.offset), why.c_str());
          if (writer) writer->write(e.timestamp, e.channel, e.data, e.size);
          continue;
        }
        const nadir::track_truth::FrameFlow frame = compare.process(&tracks, rewrite);
        if (frames && frame.count > 0) {
          std::fprintf(frames.get(), "%lld,%lld,%.6f,%.6f,%.6f,%.6e\n", static_cast<long long>(frame.utime),
                       static_cast<long long>(frame.count), frame.mean_x, frame.mean_y, frame.rms, frame.expansion);
        }
        if (writer) {
          const std::vector<uint8_t> bytes = nadir::encode_message(tracks);
          writer->write(e.timestamp, e.channel, bytes.data(), bytes.size());
        }
        continue;
      }
      if (writer && !(drop_images && e.channel == nadir::channels::kCameraImage))
        writer->write(e.timestamp, e.channel, e.data, e.size);
    }
    progress.finish();
    if (writer) writer->flush();
    const TrackTruthReport r = compare.report();
    const int64_t corrupt = reader.corrupt_records() + malformed;
    if (reader.corrupt_records() > 0)
      std::fprintf(stderr, "nadir_track_truth: warning: %s", reader.damage_report().c_str());
    if (json) {
      std::printf("%s\n", report_json(r, corrupt, scene.seed(), scene.relief_scale()).c_str());
      return 0;
    }
    std::printf("%s: seed %llu, relief_scale %g, %zu frame truths\n", in_path.c_str(),
                static_cast<unsigned long long>(scene.seed()), scene.relief_scale(), scene.frames());
    std::printf("TRACKS %lld (%lld without frame truth), tracks %lld, ray misses %lld, occluded %lld, corrupt %lld\n",
                static_cast<long long>(r.messages), static_cast<long long>(r.messages_without_truth),
                static_cast<long long>(r.tracks), static_cast<long long>(r.ray_misses),
                static_cast<long long>(r.occluded), static_cast<long long>(corrupt));
    print_stats("flow (one step)", r.flow);
    std::printf(
        "flow expansion         %+.3e per frame (about the principal point; a solver reads it as vertical "
        "motion)\n",
        r.flow_expansion_per_frame);
    for (const auto& bin : r.drift_by_age) {
      char label[64];
      if (bin.to == std::numeric_limits<int>::max())
        std::snprintf(label, sizeof label, "drift age >= %d", bin.from);
      else
        std::snprintf(label, sizeof label, "drift age %d-%d", bin.from, bin.to - 1);
      print_stats(label, bin.drift);
      std::printf("%-22s %+.3e (about the principal point); one step's at these ages %+.3e\n", "  its expansion",
                  bin.drift_expansion, bin.flow_expansion);
    }
    if (writer) std::printf("wrote %s (%s tracks)\n", out_path.c_str(), rewrite_name.c_str());
    return 0;
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "nadir_track_truth: error: %s\n", ex.what());
    return 1;
  }
}
