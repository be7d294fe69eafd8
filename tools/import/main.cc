// nadir_import: a recorded flight (photo folder, or video + .SRT / CSV) -> a
// nadir LCM log and the config nadir_replay / nadir_eval run it with.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "common/paths.h"
#include "common/progress.h"
#include "tools/import/flight_import.h"

namespace {

// A number in (0, max], `max` whole; `hint` says what to do instead of 0
// (leaving the option out is how its default is asked for).
CLI::Validator positive_at_most(int max, const std::string& hint) {
  const std::string range = "(0, " + std::to_string(max) + "]";
  return CLI::Validator(
      [max, range, hint](std::string& text) {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        const bool ok = end != text.c_str() && *end == '\0' && v > 0.0 && v <= max;
        return ok ? std::string() : "must be in " + range + " (" + hint + "), not " + text;
      },
      range);
}

}  // namespace

int main(int argc, char** argv) {
  nadir::import::ImportOptions o;
  bool json = false;
  CLI::App app{
      "Imports a recorded flight into nadir: a folder of photos (JPEG/PNG/TIFF with EXIF time and GPS, and DJI "
      "drone-dji: or senseFly sensefly: XMP attitude and height) or a video with a DJI-style .SRT or a CSV "
      "(time_s,roll_deg,pitch_deg,yaw_deg,range_m|height_m,lat_deg,lon_deg,alt_m). Writes OUT.lcmlog (CONFIG, "
      "CAMERA_IMAGE grey, INS, ALTIMETER, GROUND_TRUTH from GPS) and OUT.yaml for nadir_replay --config. "
      "Conventions: docs/own-flight.md.",
      "nadir_import"};
  app.add_option("--photos", o.photos_dir, "folder of photos (taken in file-name order)");
  app.add_option("--video", o.video, "video file (OpenCV VideoCapture)");
  app.add_option("--srt", o.srt, "DJI-style .SRT telemetry for --video");
  app.add_option("--csv", o.csv, "CSV telemetry for --video (time_s = seconds from the video's start)");
  app.add_option("--out", o.out, "output prefix: OUT.lcmlog and OUT.yaml")->required();
  app.add_option("--camera", o.camera_file,
                 "OpenCV calibration file (camera_matrix, distortion_coefficients, image_width, image_height, "
                 "optional mount_rpy_deg) at the files' size or at the working size (--scale)");
  app.add_option("--focal-px", o.focal_px,
                 "focal length in pixels of the files (no calibration file; no distortion). Without --camera or "
                 "--focal-px, photos give it: DJI XMP CalibratedFocalLength, else the EXIF 35 mm equivalent on the "
                 "sensor's native frame (docs/own-flight.md, 'The camera from the photos')");
  app.add_option("--scale", o.scale,
                 "downscale the images by this factor, intrinsics scaled with them (0, 1]; 1 = full size. Default: "
                 "the working resolution, 1/k with the smallest whole k that brings the long side to at most " +
                     std::to_string(nadir::import::kWorkingLongSidePx) +
                     " px (docs/own-flight.md, 'The working resolution')")
      ->check(positive_at_most(1, "1: full size; leave it out for the working resolution"));
  app.add_option("--interval", o.interval_s, "photo times from file order, this many seconds apart (EXIF time ignored)");
  const CLI::Validator attitude_figure = positive_at_most(static_cast<int>(nadir::import::kMaxAttitudeStddevDeg),
                                                         "leave it out for the attitude source's");
  app.add_option("--attitude-stddev-deg", o.attitude_stddev_deg,
                 "roll/pitch accuracy of the recorded attitude (1 sigma, degrees, per frame; at most " +
                     std::to_string(static_cast<int>(nadir::import::kMaxAttitudeStddevDeg)) +
                     "). Default: the attitude source's (docs/own-flight.md, 'How well the attitude is known')")
      ->check(attitude_figure);
  app.add_option("--heading-stddev-deg", o.heading_stddev_deg,
                 "heading accuracy of the recorded attitude (1 sigma, degrees, per frame). Default: the attitude "
                 "source's")
      ->check(attitude_figure);
  app.add_flag("--skip-bad", o.skip_bad, "skip and count bad photos / frames / telemetry lines instead of failing");
  app.add_option("--config", o.config_path, "base config to add the camera and overrides to (default config/default.yaml)");
  app.add_flag("--json", json, "print a JSON summary on stdout");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (o.config_path.empty()) o.config_path = nadir::default_config_path();
    o.progress = nadir::stderr_is_terminal();
    const nadir::import::ImportSummary s = nadir::import::run_import(o);
    std::fputs(nadir::import::summary_text(s).c_str(), stderr);
    if (json) std::printf("%s\n", nadir::import::summary_json(s).c_str());
    return 0;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "nadir_import: %s (see --help)\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_import: error: %s\n", e.what());
    return 2;
  }
}
