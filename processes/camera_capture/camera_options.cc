#include "processes/camera_capture/camera_options.h"

#include <algorithm>

namespace nadir {

CameraOptions CameraOptions::FromConfig(const Config& c) {
  CameraOptions o;
  c.require_known_keys({"id", "pixel_format", "roi", "binning", "exposure", "gain_db", "frame_rate_hz", "trigger",
                        "gige", "stream_buffers", "optional_features"});
  o.id = c.get<std::string>("id", o.id);
  o.pixel_format = c.get<std::string>("pixel_format", o.pixel_format);
  const Config roi = c.section_or_empty("roi");
  roi.require_known_keys({"x", "y", "width", "height"});
  o.roi_x = roi.get_in_range<int>("x", o.roi_x, 0, 65535);
  o.roi_y = roi.get_in_range<int>("y", o.roi_y, 0, 65535);
  o.roi_width = roi.get_in_range<int>("width", o.roi_width, 0, 65535);
  o.roi_height = roi.get_in_range<int>("height", o.roi_height, 0, 65535);
  const std::vector<int> binning = c.get<std::vector<int>>("binning", {o.binning_x, o.binning_y});
  if (binning.size() != 2) throw c.error("binning", "must be [horizontal, vertical]");
  o.binning_x = binning[0];
  o.binning_y = binning[1];
  const Config exposure = c.section_or_empty("exposure");
  exposure.require_known_keys({"mode", "time_us", "auto_min_us", "auto_max_us"});
  o.exposure_mode = exposure.get<std::string>("mode", o.exposure_mode);
  o.exposure_us = exposure.get_in_range<double>("time_us", o.exposure_us, 1.0, 1e6);
  o.exposure_auto_min_us = exposure.get_in_range<double>("auto_min_us", o.exposure_auto_min_us, 1.0, 1e6);
  o.exposure_auto_max_us = exposure.get_in_range<double>("auto_max_us", o.exposure_auto_max_us, 1.0, 1e6);
  o.gain_db = c.get_in_range<double>("gain_db", o.gain_db, -20.0, 60.0);
  o.frame_rate_hz = c.get_in_range<double>("frame_rate_hz", o.frame_rate_hz, 0.1, 1000.0);
  const Config trigger = c.section_or_empty("trigger");
  trigger.require_known_keys({"mode", "line", "activation", "debounce_us", "software_rate_hz"});
  o.trigger_mode = trigger.get<std::string>("mode", o.trigger_mode);
  o.trigger_line = trigger.get<std::string>("line", o.trigger_line);
  o.trigger_activation = trigger.get<std::string>("activation", o.trigger_activation);
  o.trigger_debounce_us = trigger.get_in_range<double>("debounce_us", o.trigger_debounce_us, 0.0, 1e5);
  o.software_trigger_rate_hz = trigger.get_in_range<double>("software_rate_hz", o.software_trigger_rate_hz, 0.0, 1000.0);
  const Config gige = c.section_or_empty("gige");
  gige.require_known_keys({"packet_size", "packet_delay_ns"});
  o.packet_size = gige.get_in_range<int>("packet_size", o.packet_size, 0, 16000);
  o.packet_delay_ns = gige.get_in_range<int>("packet_delay_ns", o.packet_delay_ns, 0, 100000000);
  o.stream_buffers = c.get_in_range<int>("stream_buffers", o.stream_buffers, 2, 256);
  o.optional_features = c.get<std::vector<std::string>>("optional_features", o.optional_features);
  try {
    o.Check();
  } catch (const ConfigError& e) {
    throw ConfigError(c.source() + ": " + e.what());
  }
  return o;
}

void CameraOptions::Check() const {
  const std::string s = "camera_capture.camera";
  const bool known_format = pixel_format == "Mono8" || pixel_format == "Mono10" || pixel_format == "Mono12" ||
                            pixel_format == "Mono16" ||
                            (pixel_format.rfind("Bayer", 0) == 0 && pixel_format.size() == 9 &&
                             pixel_format.substr(7) == "8");
  require_option(known_format, s, "pixel_format",
                 "= '" + pixel_format + "' is not one of Mono8, Mono10, Mono12, Mono16, BayerRG8, BayerGR8, BayerGB8, BayerBG8");
  require_option(binning_x >= 1 && binning_x <= 16 && binning_y >= 1 && binning_y <= 16, s, "binning",
                 "must be in [1, 16]");
  require_option(exposure_mode == "fixed" || exposure_mode == "auto", s, "exposure.mode",
                 "= '" + exposure_mode + "' is not fixed or auto");
  require_option(exposure_auto_min_us <= exposure_auto_max_us, s, "exposure.auto_min_us",
                 "must be <= exposure.auto_max_us");
  require_option(trigger_mode == "free_run" || trigger_mode == "software" || trigger_mode == "hardware", s,
                 "trigger.mode", "= '" + trigger_mode + "' is not free_run, software or hardware");
  require_option(stream_buffers >= 2, s, "stream_buffers", "must be >= 2");
}

bool CameraOptions::is_optional(const std::string& feature) const {
  return std::find(optional_features.begin(), optional_features.end(), feature) != optional_features.end();
}

}  // namespace nadir
