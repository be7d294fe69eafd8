// nadir_export: a nadir_sim log -> a DJI-style photo survey or a video with
// SRT/CSV telemetry, so that nadir_import can bring a flight back whose truth
// is known (the round trip); or any nadir log -> MCAP for Foxglove.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <exception>

#include "common/json_writer.h"
#include "common/robust_stats.h"
#include "common/progress.h"
#include "tools/export/exporter.h"
#include "tools/export/mcap_export.h"

namespace {

int export_mcap_file(const std::string& in, const std::string& out, nadir::McapExportOptions options,
                     const std::vector<double>& origin, bool json) {
  if (!origin.empty()) {
    options.origin_from_ins = false;
    options.origin = {origin[0], origin[1], origin[2]};
  }
  const nadir::McapExportStats s = nadir::export_mcap(in, out, options);
  if (json) {
    nadir::JsonWriter j;
    j.begin_object()
        .field("in", in)
        .field("out", out)
        .field("log_events", s.log_events)
        .field("mcap_messages", s.messages)
        .field("chunks", static_cast<int64_t>(s.chunks))
        .field("undecodable", s.undecodable)
        .field("images_decimated", s.images_decimated)
        .field("corrupt_records", s.corrupt_records);
    j.key("lcm_messages").begin_object();
    for (const auto& [channel, n] : s.lcm_messages) j.field(channel, n);
    j.end_object().key("skipped_channels").begin_object();
    for (const auto& [channel, n] : s.skipped) j.field(channel, n);
    j.end_object().end_object();
    std::printf("%s\n", j.str().c_str());
  }
  std::fprintf(stderr, "nadir_export: %s: %lld log events -> %lld MCAP messages in %u chunks into %s", in.c_str(),
               static_cast<long long>(s.log_events), static_cast<long long>(s.messages), s.chunks, out.c_str());
  for (const auto& [channel, n] : s.skipped)
    std::fprintf(stderr, "; skipped %s (%lld, no topic)", channel.c_str(), static_cast<long long>(n));
  if (s.undecodable) std::fprintf(stderr, "; %lld undecodable", static_cast<long long>(s.undecodable));
  std::fprintf(stderr, "\n");
  return 0;
}

using nadir::exporter::PhotoExportResult;

// Pairs whose heading changed by more than this are "across a turn".
constexpr double kTurnPairDeg = 30.0;

void print_photos(const PhotoExportResult& r, const std::string& in, const std::string& out, bool json) {
  std::vector<double> line_overlaps;
  int64_t turn_pairs = 0;
  double min_turn_overlap = 1.0, max_heading_change = 0.0;
  for (const auto& p : r.photos) {
    if (p.overlap_with_previous < 0) continue;
    if (std::fabs(p.heading_change_deg) > kTurnPairDeg) {
      ++turn_pairs;
      min_turn_overlap = std::min(min_turn_overlap, p.overlap_with_previous);
    } else {
      line_overlaps.push_back(p.overlap_with_previous);
    }
    max_heading_change = std::max(max_heading_change, std::fabs(p.heading_change_deg));
  }
  std::sort(line_overlaps.begin(), line_overlaps.end());
  const double median = line_overlaps.empty() ? 0.0 : nadir::median(line_overlaps, nadir::EvenMedian::kUpper);
  const double lo = line_overlaps.empty() ? 0.0 : line_overlaps.front();
  const double hi = line_overlaps.empty() ? 0.0 : line_overlaps.back();
  const double span_s = (r.photos.back().utime - r.photos.front().utime) * 1e-6;
  if (json) {
    nadir::JsonWriter j;
    j.begin_object()
        .field("in", in)
        .field("out", out)
        .field("camera_file", r.camera_file)
        .field("attitude_source", r.attitude_source)
        .field("photos_written", static_cast<int64_t>(r.photos.size()))
        .field("skipped_in_turns", r.skipped_in_turns)
        .field("ticks_without_image", r.ticks_without_image)
        .field("first_utime", r.photos.front().utime)
        .field("last_utime", r.photos.back().utime)
        .field("time_span_s", span_s)
        .field("line_overlap_min", lo)
        .field("line_overlap_median", median)
        .field("line_overlap_max", hi)
        .field("turn_pairs", turn_pairs)
        .field("turn_overlap_min", turn_pairs > 0 ? min_turn_overlap : 0.0)
        .field("max_heading_change_deg", max_heading_change);
    j.key("photos").begin_array();
    for (const auto& p : r.photos) {
      j.begin_object()
          .field("file", p.file)
          .field("utime", p.utime)
          .field("overlap_with_previous", p.overlap_with_previous)
          .field("heading_change_deg", p.heading_change_deg)
          .field("stored_turn_deg", p.stored_turn_deg)
          .field("north_m", p.north_m)
          .field("east_m", p.east_m)
          .end_object();
    }
    j.end_array().end_object();
    std::printf("%s\n", j.str().c_str());
  }
  std::fprintf(stderr,
               "nadir_export: %zu photos over %.1f s into %s (%lld ticks skipped in turns, %lld without image); "
               "overlap on the lines %.0f-%.0f %% (median %.0f %%), %lld pairs across turns (min overlap %.0f %%, "
               "largest heading change %.1f deg); attitude from %s\n",
               r.photos.size(), span_s, out.c_str(), static_cast<long long>(r.skipped_in_turns),
               static_cast<long long>(r.ticks_without_image), 100 * lo, 100 * hi, 100 * median,
               static_cast<long long>(turn_pairs), turn_pairs > 0 ? 100 * min_turn_overlap : 0.0, max_heading_change,
               r.attitude_source.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Exports a nadir_sim log as a real flight would come: a DJI-style photo survey (JPEG with EXIF/XMP "
               "written through libexiv2, images turned so the top is forward, camera.yaml for the turned image) "
               "or an MJPG AVI video with a DJI-style SRT and a generic CSV. Positions are the simulator's truth "
               "(GPS); attitudes the truth at each exposure (--attitude truth) or the INS's measured attitude "
               "(--attitude ins). Pipeline: nadir_sim --profile survey --out SIM.lcmlog && "
               "nadir_export photos --in SIM.lcmlog --out DIR. Also any nadir log as MCAP for Foxglove "
               "(nadir_export mcap --in LOG --out FLIGHT.mcap; docs/foxglove.md).",
               "nadir_export"};
  app.require_subcommand(1);
  std::string in, attitude = "truth";
  std::vector<double> mcap_origin;
  bool json = false;

  nadir::exporter::PhotoExportOptions photo;
  std::string out_dir;
  CLI::App* photos = app.add_subcommand("photos", "photo survey: DIR/DJI_NNNN.JPG + DIR/camera.yaml");
  photos->add_option("--in", in, "nadir_sim log")->required();
  photos->add_option("--out", out_dir, "output folder (created)")->required();
  photos->add_option("--interval", photo.interval_s, "seconds of sensor time between photos (default 2.0)");
  photos->add_option("--max-yaw-rate-dps", photo.max_yaw_rate_dps,
                     "no photo while the heading turns faster than this, deg/s (default 3)");
  photos->add_option("--quality", photo.quality, "JPEG quality 1-100 (default 95)");
  photos->add_option("--pixel-pitch-um", photo.pixel_pitch_um,
                     "nominal pixel pitch for the EXIF focal length in mm (default 5.86)");
  photos->add_option("--attitude", attitude, "truth (default) or ins: the attitude written into the photos");
  photos->add_option("--model", photo.model, "EXIF Model to write (default: nadir_sim downward camera)");
  photos->add_flag("--crop-16-9", photo.crop_16_9,
                   "write 16:9 crops (full width, centre rows) of a 4:3 sensor of the photo's width: EXIF gives the "
                   "35 mm equivalent of the 4:3 frame; camera.yaml describes the crop");
  photos->add_flag("--dji-calibration", photo.dji_calibration,
                   "write the true focal length and principal point as XMP drone-dji:CalibratedFocalLength / "
                   "CalibratedOpticalCenterX/Y");
  photos->add_flag("--dji-dewarp", photo.dji_dewarp,
                   "write the lens calibration (focal lengths, principal point, k1 k2 p1 p2 k3) as XMP "
                   "drone-dji:DewarpData with DewarpFlag 0, as DJI's enterprise cameras do");
  photos->add_option("--turn-return-lines", photo.return_lines_turn_deg,
                     "store the return lines' photos (heading > 90 deg from the first photo's) turned clockwise by "
                     "0, 90, 180 or 270 deg in their pixels, EXIF Orientation 1, as a photo viewer re-saves them");
  photos->add_option("--yaw-offset-deg", photo.yaw_offset_deg,
                     "write the flight and gimbal yaw this many degrees off the true heading (a disturbed compass)");
  photos->add_flag("--json", json, "print a machine-readable summary on stdout");

  nadir::exporter::VideoExportOptions video;
  std::string video_path, srt_path, csv_path, calibration_path;
  CLI::App* vid = app.add_subcommand(
      "video", "MJPG AVI + DJI-style SRT per frame (+ CSV: time_s since the first frame, body attitude, height above "
               "take-off, GPS)");
  vid->add_option("--in", in, "nadir_sim log")->required();
  vid->add_option("--out", video_path, "video file (.avi, MJPG)")->required();
  vid->add_option("--srt", srt_path, "DJI-style subtitle file")->required();
  vid->add_option("--csv", csv_path, "generic telemetry CSV (optional)");
  vid->add_option("--camera", calibration_path, "also write the frames' OpenCV calibration file (camera.yaml)");
  bool no_range = false;
  vid->add_flag("--no-range", no_range, "no [range:] (laser altimeter) in the SRT: height from rel_alt only");
  vid->add_option("--every", video.every, "every Nth camera frame (default 1)");
  vid->add_option("--attitude", attitude, "truth (default) or ins");
  vid->add_flag("--json", json, "print a machine-readable summary on stdout");
  nadir::McapExportOptions mcap;
  std::string mcap_path;
  CLI::App* mcap_cmd = app.add_subcommand(
      "mcap", "any nadir log -> MCAP with the Foxglove bridge's topics and JSON schemas (opens in Foxglove with "
              "config/foxglove/nadir_layout.json; docs/foxglove.md)");
  mcap_cmd->add_option("--in", in, "nadir LCM log")->required();
  mcap_cmd->add_option("--out", mcap_path, "MCAP file to write")->required();
  mcap_cmd->add_option("--image-rate", mcap.image_rate_hz, "CAMERA_IMAGE at most this often, Hz (default 0: every frame)")
      ->check(CLI::Range(0.0, 1000.0));
  mcap_cmd->add_option("--origin", mcap_origin, "POSE's NED origin: latitude_deg longitude_deg height_m (default: the INS position at the first POSE)")
      ->expected(3);
  mcap_cmd->add_flag("--json", json, "print a machine-readable summary on stdout");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*mcap_cmd) return export_mcap_file(in, mcap_path, mcap, mcap_origin, json);
    const auto log = nadir::exporter::SimLog::load(in);
    if (*photos) {
      photo.attitude = nadir::exporter::parse_attitude_source(attitude);
      photo.progress = nadir::stderr_is_terminal();
      print_photos(nadir::exporter::export_photos(*log, out_dir, photo), in, out_dir, json);
    } else {
      video.attitude = nadir::exporter::parse_attitude_source(attitude);
      video.range = !no_range;
      video.progress = nadir::stderr_is_terminal();
      const auto r = nadir::exporter::export_video(*log, video_path, srt_path, csv_path, video);
      if (!calibration_path.empty()) {
        nadir::exporter::write_calibration(nadir::exporter::turned_camera(log->camera()), calibration_path);
      }
      if (json) {
        nadir::JsonWriter j;
        j.begin_object()
            .field("in", in)
            .field("video", video_path)
            .field("srt", srt_path)
            .field("csv", csv_path)
            .field("frames", r.frames)
            .field("fps", r.fps)
            .field("frames_with_range", r.frames_with_range)
            .field("first_utime", r.first_utime)
            .field("last_utime", r.last_utime)
            .field("time_span_s", (r.last_utime - r.first_utime) * 1e-6)
            .end_object();
        std::printf("%s\n", j.str().c_str());
      }
      std::fprintf(stderr, "nadir_export: %lld frames at %.2f fps over %.1f s into %s + %s%s%s\n",
                   static_cast<long long>(r.frames), r.fps, (r.last_utime - r.first_utime) * 1e-6,
                   video_path.c_str(), srt_path.c_str(), csv_path.empty() ? "" : " + ", csv_path.c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_export: %s\n", e.what());
    return 1;
  }
  return 0;
}
