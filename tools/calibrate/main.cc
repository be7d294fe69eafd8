// nadir_calibrate: camera boresight, camera time offset, focal scale and
// altimeter scale/bias from a flight segment (docs/calibration.md).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <fstream>
#include <vector>

#include "common/config.h"
#include "common/paths.h"
#include "tools/calibrate/calibration.h"

int main(int argc, char** argv) {
  CLI::App app{"Estimates the camera-body boresight (roll, pitch, yaw), the camera-INS time offset, the focal length "
               "scale and the altimeter scale and bias, each with a 1-sigma uncertainty, from a flight segment: a log "
               "with INS (attitude and GNSS position), TRACKS (replay the tracker over the flight: nadir_replay "
               "--nodes tracker) and ALTIMETER, plus GROUND_TRUTH or --ground-height-m for the altimeter; with "
               "VO_DELTA (replay vo_solver too) also the image scale against GNSS. Warns when "
               "the flight does not excite a parameter. Writes a YAML config fragment (--out, or stdout).",
               "nadir_calibrate"};
  std::string log_path, config_path, out_path;
  bool json = false, no_focal = false, no_distortion = false;
  nadir::calibrate::CalibrationOptions options;
  double ground_height_m = 0.0;
  app.add_option("--log", log_path, "log with INS, TRACKS, ALTIMETER (and GROUND_TRUTH)")->required();
  app.add_option("--config", config_path,
                 "config whose camera: section the TRACKS were normalized with (default: config/default.yaml)");
  std::vector<std::string> overlays;
  app.add_option("--config-overlay", overlays,
                 "YAML fragment merged into the config key by key (repeatable), e.g. the installation drawing's lever "
                 "arms or a first pass's fragment");
  app.add_option("--out", out_path, "write the YAML config fragment here (default: stdout)");
  auto* ground = app.add_option("--ground-height-m", ground_height_m,
                                "flat ground height (INS height datum) for the altimeter when the log has no GROUND_TRUTH");
  app.add_option("--attitude-smoothing-s", options.attitude_smoothing_s,
                 "half-width (s) of the centred average pulling the integrated INS rates to the INS attitude (default 3; without rates: of the attitude itself, at most 0.05)");
  app.add_option("--cluster-s", options.cluster_s, "span over which residuals share INS errors (default 2)");
  std::vector<double> ins_accuracy;
  app.add_option("--ins-attitude-accuracy-deg", ins_accuracy,
                 "the INS's slowly varying attitude error, roll pitch yaw (deg, datasheet): added to the boresight "
                 "sigmas (the boresight is relative to the INS)")
      ->expected(3);
  app.add_option("--ins-attitude-correlation-s", options.ins_attitude_correlation_s,
                 "correlation time (s) of that error (a Gauss-Markov process, datasheet or Allan variance): the "
                 "boresight sigmas then carry the sigma of its mean over the segment, which shrinks on a long flight "
                 "(default 0: a constant error)");
  app.add_flag("--no-focal", no_focal, "hold the focal length scale at 1 (and the distortion at the configured)");
  app.add_flag("--no-distortion", no_distortion,
               "hold the radial distortion k1, k2 at the configured values (by default their errors are fitted with "
               "the focal scale and written into camera.distortion)");
  std::string gps_scale;
  app.add_option("--gps-scale", gps_scale,
                 "write the image scale against GNSS (GNSS baseline / VO step over the log's solved VO_DELTA; always "
                 "reported when the log has them) into the fragment as the focal length (focal: an undocumented "
                 "camera; implies --no-focal) or as the altimeter scale (altimeter: a barometric height)")
      ->check(CLI::IsMember({"focal", "altimeter"}));
  app.add_flag("--scale-only", options.gps_scale_only,
               "with --gps-scale: the fragment sets only the focal length or the altimeter scale, everything else "
               "stays as configured (a survey flight that does not excite the boresight)");
  app.add_option("--from-s", options.segment_from_s, "use the flight from this many seconds after its first INS sample");
  app.add_option("--until-s", options.segment_until_s,
                 "... up to this many seconds (the rest is left for checking the result on data it was not fitted on)");
  app.add_flag("--json", json, "print the estimates as JSON on stdout (the fragment then needs --out)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*ground) options.ground_height_m = ground_height_m;
    for (size_t i = 0; i < ins_accuracy.size() && i < 3; ++i) options.ins_attitude_accuracy_deg[i] = ins_accuracy[i];
    options.estimate_focal = !no_focal && gps_scale != "focal";
    options.estimate_distortion = !no_distortion;
    if (gps_scale == "focal") options.gps_scale_target = nadir::calibrate::CalibrationOptions::GpsScaleTarget::kFocal;
    if (gps_scale == "altimeter")
      options.gps_scale_target = nadir::calibrate::CalibrationOptions::GpsScaleTarget::kAltimeter;
    options.Check();
    const std::string config_file = config_path.empty() ? nadir::default_config_path() : config_path;
    nadir::Config config = nadir::Config::load_file(config_file);
    for (const std::string& overlay : overlays) config.apply_overlay(nadir::Config::load_file(overlay));
    const nadir::calibrate::FlightData data = nadir::calibrate::load_flight(log_path, !json);
    if (data.corrupt_records > 0)
      std::fprintf(stderr, "nadir_calibrate: warning: %s: %lld corrupt record(s) skipped\n", log_path.c_str(),
                   static_cast<long long>(data.corrupt_records));
    const nadir::calibrate::CalibrationResult result = nadir::calibrate::calibrate(data, config, options);
    const std::string fragment = result.config_fragment(log_path);
    if (!out_path.empty()) {
      std::ofstream out(out_path);
      if (!(out << fragment)) throw std::runtime_error(out_path + ": cannot write");
    }
    if (json) {
      std::printf("%s\n", result.json().c_str());
    } else {
      if (out_path.empty()) std::printf("%s", fragment.c_str());
      for (const std::string& w : result.warnings) std::fprintf(stderr, "nadir_calibrate: warning: %s\n", w.c_str());
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_calibrate: error: %s\n", e.what());
    return 1;
  }
}
