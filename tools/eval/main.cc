// nadir_eval: POSE against GROUND_TRUTH, the paper's Table 1 / Fig. 7 figures.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>

#include "common/channels.h"
#include "common/paths.h"
#include "common/status.h"
#include "tools/eval/eval_outputs.h"
#include "tools/eval/trajectory_metrics.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  CLI::App app{"Evaluates POSE against GROUND_TRUTH aligned by sensor time: distance flown, final error and "
               "error as % of distance (paper Table 1), drift over time and velocity errors (Fig. 7), yaw error. "
               "Writes metrics.json, series.csv, pairs.csv (each VO_DELTA against the truth step), trajectory.png, "
               "drift.png, velocity_errors.png, "
               "trajectory.geojson and trajectory.kml into --out.",
               "nadir_eval"};
  std::string log_path, truth_path, out_dir;
  bool json = false;
  bool no_plots = false;
  int64_t truth_shift_us = 0;
  app.add_option("--log", log_path, "log with POSE (a replay output or a live capture)")->required();
  app.add_option("--truth", truth_path, "log with GROUND_TRUTH (default: the same log)");
  app.add_option("--out", out_dir, "output folder (created)")->required();
  app.add_option("--truth-shift-us", truth_shift_us,
                 "added to the sensor times of --truth (a simulator log played on another clock, e.g. the hil set)");
  app.add_flag("--json", json, "print metrics.json to stdout instead of the summary");
  app.add_flag("--no-plots", no_plots, "skip the PNG plots (no matplotlib needed)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    const nadir::EvalData data = nadir::load_eval_data(log_path, truth_path, truth_shift_us);
    // A damaged or holed capture still evaluates, but never silently.
    if (data.corrupt_records > 0 || data.truncated) {
      std::fprintf(stderr, "nadir_eval: warning: %s: %lld corrupt record(s)%s; evaluated what could be read\n%s",
                   log_path.c_str(), static_cast<long long>(data.corrupt_records),
                   data.truncated ? ", truncated" : "", data.damage_report.c_str());
    }
    // A photo flight's intervals are summarised in the report, not warned about.
    if (!data.holes.empty()) {
      std::fprintf(stderr, "nadir_eval: warning: %s: %zu hole(s) in the capture\n%s", log_path.c_str(),
                   data.holes.size(), nadir::format_log_holes(data.holes).c_str());
    }
    const std::string accounting = nadir::format_capture_accounting(data.accounting);
    if (!accounting.empty()) {
      std::fprintf(stderr, "nadir_eval: warning: %s: messages lost or unaccounted\n%s", log_path.c_str(),
                   accounting.c_str());
    }
    const nadir::EvalResult result = nadir::evaluate(data);
    if (!result.metrics.footprint_problem.empty() && !data.deltas.empty()) {
      std::fprintf(stderr, "nadir_eval: warning: %s: no pair footprints (%s)\n", log_path.c_str(),
                   result.metrics.footprint_problem.c_str());
    }
    fs::create_directories(out_dir);
    const std::string metrics = nadir::metrics_json(result.metrics);
    std::ofstream(out_dir + "/metrics.json") << metrics << "\n";
    nadir::write_series_csv(result, out_dir + "/series.csv");
    nadir::write_pairs_csv(result.pairs, out_dir + "/pairs.csv");
    nadir::write_map_fixes_csv(result.metrics.map_fixes, out_dir + "/map_fixes.csv");
    nadir::write_geojson(result, out_dir + "/trajectory.geojson");
    nadir::write_kml(result, out_dir + "/trajectory.kml");
    if (!no_plots) {
      const std::string script = nadir::checkout_root() + "/tools/eval/plot_eval.py";
      const std::string command = "/usr/bin/python3 '" + script + "' '" + out_dir + "'";
      if (std::system(command.c_str()) != 0) {
        std::fprintf(stderr, "nadir_eval: error: plotting failed (%s)\n", command.c_str());
        return 1;
      }
    }
    {
      // The same figures as one self-contained page (report_html.py; no matplotlib needed).
      const std::string html_command =
          "/usr/bin/python3 '" + nadir::checkout_root() + "/tools/eval/report_html.py' '" + out_dir + "'";
      if (std::system(html_command.c_str()) != 0) {
        std::fprintf(stderr, "nadir_eval: error: the HTML report failed (%s)\n", html_command.c_str());
        return 1;
      }
    }
    const nadir::EvalMetrics& m = result.metrics;
    if (json) {
      std::printf("%s\n", metrics.c_str());
    } else {
      std::printf("distance flown      %10.1f m over %.1f s\n", m.distance_m, m.duration_s);
      std::printf("final error         %10.2f m (horizontal %.2f m, vertical %.2f m)\n", m.final_error_3d_m,
                  m.final_error_h_m, m.final_error_v_m);
      std::printf("error / distance    %10.3f %% (horizontal %.3f %%, vertical %.3f %%)\n", m.error_pct_3d,
                  m.error_pct_h, m.error_pct_v);
      std::printf("horizontal error    %10.2f m at the 95th percentile over the flight, %.2f m max\n",
                  m.p95_error_h_m, m.max_error_h_m);
      const nadir::MapFixMetrics& f = m.map_fixes;
      if (f.fixes > 0 || f.applied > 0 || f.rejected > 0) {
        std::printf("map fixes           %10lld on MAP_FIX, %lld applied, %lld rejected by the gate; error %.2f m "
                    "median, %.2f m p95, %.2f m max (sigma %.2f m median); %lld beyond 3 sigma (max %.2f)\n",
                    static_cast<long long>(f.fixes), static_cast<long long>(f.applied),
                    static_cast<long long>(f.rejected), f.error_median_m, f.error_p95_m, f.error_max_m,
                    f.sigma_median_m, static_cast<long long>(f.beyond_3_sigma), f.mahalanobis_max);
      }
      std::printf("velocity error      %10.3f m/s rms horizontal\n", m.rms_velocity_error_h);
      std::printf("yaw error           %10.3f deg rms (fused yaw vs truth yaw at each pose%s)\n", m.rms_yaw_error_deg,
                  m.imported ? "; imported: the truth is the recorded yaw, the estimator's INS input" : "");
      if (m.nees_samples > 0) {
        std::printf("uncertainty         %10.2f horizontal NEES, mean over %lld poses (2 when the reported sigma is "
                    "right, above: over-confident), %.1f %% inside its 95 %% bound; %.2f %% of poses beyond the "
                    "protection level\n",
                    m.nees_h_mean, static_cast<long long>(m.nees_samples), m.nees_h_within_95_pct, m.pl_exceeded_pct);
      }
      std::printf("frames              %10lld images, %lld dropped, %lld poses (%lld flagged); %lld CAMERA_IMAGE, "
                  "TRACKS and VO_DELTA record(s) not the pipeline's, left out\n",
                  static_cast<long long>(m.images), static_cast<long long>(m.frames_dropped),
                  static_cast<long long>(m.poses), static_cast<long long>(m.poses_flagged),
                  static_cast<long long>(m.records_not_pipeline));
      if (!m.coasts.empty()) {
        double added_h = 0, added_v = 0, longest = 0;
        for (const nadir::CoastEpisode& c : m.coasts) {
          added_h = std::max(added_h, c.added_h_m);
          added_v = std::max(added_v, std::fabs(c.added_v_m));
          longest = std::max(longest, c.duration_s);
        }
        std::printf("coasting            %10zu episode(s), %.1f s in all (longest %.1f s); error added by one: "
                    "at most %.2f m horizontal, %.2f m vertical\n",
                    m.coasts.size(), m.coast_s, longest, added_h, added_v);
      }
      if (m.pairs > 0) {
        const std::string not_solved =
            m.pairs_not_solved_flagged > 0 ? ", " + std::to_string(m.pairs_not_solved_flagged) +
                                                 " not solved (flagged: " + m.pairs_not_solved_why + ")"
                                           : "";
        std::printf("frame pairs         %10lld VO_DELTA, %lld solved (%.1f %%)%s, horizontal error per pair %.1f %% "
                    "of the step median, %.1f %% p90 (median step %.1f m)\n",
                    static_cast<long long>(m.pairs), static_cast<long long>(m.pairs_solved), m.pairs_solved_pct,
                    not_solved.c_str(), m.pair_error_pct_median, m.pair_error_pct_p90, m.pair_step_median_m);
        if (m.pairs_overlapping_solved_pct >= 0) {
          std::printf("pair footprints     %10lld pairs share no ground (truth poses, level ground); %.1f %% of the "
                      "%lld that do solved\n",
                      static_cast<long long>(m.pairs_apart), m.pairs_overlapping_solved_pct,
                      static_cast<long long>(m.pairs - m.pairs_apart));
        }
      }
      for (const nadir::ChannelIntervals& c : data.photo_intervals) {
        if (c.channel != nadir::channels::kCameraImage) continue;
        std::printf("photo intervals     %s (a photo flight: irregular by nature, not capture holes)\n",
                    nadir::format_channel_interval(c).c_str());
      }
      if (!m.latency_measured) {
        std::printf("latency             not measured: %s\n",
                    m.imported ? "an imported flight (its log times are the photos' or frames' sensor times)"
                               : "a lockstep replay (its log times are the input log's, not when anything ran)");
      } else {
        std::printf("latency             %10.1f ms p50, %.1f ms p99, %.1f ms worst (POSE logged - frame sensor time; "
                    "live runs only)\n",
                    m.latency_p50_ms, m.latency_p99_ms, m.latency_max_ms);
        std::printf("latency by stage   ");
        for (const char* stage : {"CAMERA_IMAGE", "TRACKS", "VO_DELTA", "POSE"}) {
          const auto it = data.stage_latency_ms.find(stage);
          if (it == data.stage_latency_ms.end()) continue;
          std::printf("  %s %.1f/%.1f/%.1f", stage, nadir::percentile(it->second, 50),
                      nadir::percentile(it->second, 99), nadir::percentile(it->second, 100));
        }
        std::printf("  (p50/p99/worst ms)\n");
        if (!data.after_image_latency_ms.empty()) {
          std::printf("latency after image %10.1f ms p50, %.1f ms p99, %.1f ms worst (POSE logged - CAMERA_IMAGE "
                      "logged: the estimator without the image source)\n",
                      m.after_image_latency_p50_ms, m.after_image_latency_p99_ms, m.after_image_latency_max_ms);
        }
      }
      // Counters from each process's last STATUS; its publish latency over
      // the whole run (the last period may have published nothing).
      for (const auto& [name, s] : data.last_status) {
        std::string latency = m.latency_measured ? "latency -" : "";
        const auto p50 = data.publish_p50_ms.find(name);
        if (m.latency_measured && p50 != data.publish_p50_ms.end()) {
          const std::vector<float>& p99 = data.publish_p99_ms.at(name);
          char text[128];
          std::snprintf(text, sizeof text,
                        "publish latency p50 %.1f ms, p99 %.1f ms (medians of 1 s periods; worst p99 %.1f ms)",
                        nadir::percentile(p50->second, 50), nadir::percentile(p99, 50),
                        *std::max_element(p99.begin(), p99.end()));
          latency = text;
        }
        std::printf("process %-12s rx %lld tx %lld dropped %lld errors %lld malformed %lld%s%s%s%s\n", name.c_str(),
                    static_cast<long long>(s.received), static_cast<long long>(s.published),
                    static_cast<long long>(s.dropped), static_cast<long long>(s.errors),
                    static_cast<long long>(s.malformed), latency.empty() ? "" : " ", latency.c_str(),
                    s.detail.empty() ? "" : " -- ",
                    s.detail.c_str());
      }
      std::printf("capture             %10lld corrupt record(s)%s, %zu hole(s), %lld missing, %lld unaccounted, "
                  "%lld kernel-dropped datagram(s)%s\n",
                  static_cast<long long>(data.corrupt_records), data.truncated ? ", truncated" : "", data.holes.size(),
                  static_cast<long long>(data.accounting.missing_total()),
                  static_cast<long long>(result.metrics.capture_unaccounted),
                  static_cast<long long>(data.accounting.udp_rx_drops_total()),
                  data.holes.empty() && accounting.empty() ? "" : " (listed on stderr)");
      std::printf("report              %s\n", out_dir.c_str());
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_eval: error: %s\n", e.what());
    return 1;
  }
}
