#include "processes/camera_capture/aravis_camera.h"

#include <arv.h>

#include <cmath>
#include <sstream>

namespace nadir {

namespace {

const char* kSection = "camera_capture.camera.";

// Communication failures are worth a retry; anything else is the camera
// refusing what config asked for.
[[noreturn]] void throw_gerror(GError* error, const std::string& what) {
  const std::string message = what + ": " + (error != nullptr ? error->message : "unknown error");
  bool unavailable = false;
  if (error != nullptr && error->domain == ARV_DEVICE_ERROR) {
    unavailable = error->code == ARV_DEVICE_ERROR_NOT_CONNECTED || error->code == ARV_DEVICE_ERROR_TIMEOUT ||
                  error->code == ARV_DEVICE_ERROR_TRANSFER_ERROR || error->code == ARV_DEVICE_ERROR_PROTOCOL_ERROR ||
                  error->code == ARV_DEVICE_ERROR_NOT_CONTROLLER || error->code == ARV_DEVICE_ERROR_NOT_FOUND;
  }
  if (error != nullptr) g_error_free(error);
  if (unavailable) throw CameraUnavailable(message);
  throw CameraConfigError(message);
}

void on_control_lost(ArvDevice*, gpointer flag) { static_cast<std::atomic<bool>*>(flag)->store(true); }

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

}  // namespace

std::vector<std::string> AravisCamera::list_devices() {
  arv_update_device_list();
  std::vector<std::string> devices;
  const unsigned n = arv_get_n_devices();
  for (unsigned i = 0; i < n; ++i) {
    const char* id = arv_get_device_id(i);
    const char* serial = arv_get_device_serial_nbr(i);
    devices.push_back(std::string(id ? id : "?") + " (serial " + (serial ? serial : "?") + ")");
  }
  return devices;
}

AravisCamera::AravisCamera(const CameraOptions& options) : options_(options) {
  options_.Check();
  arv_update_device_list();
  const unsigned n = arv_get_n_devices();
  std::string chosen;
  for (unsigned i = 0; i < n && chosen.empty(); ++i) {
    const char* id = arv_get_device_id(i);
    const char* serial = arv_get_device_serial_nbr(i);
    if (id == nullptr) continue;
    if (options_.id.empty() || options_.id == id || (serial != nullptr && options_.id == serial)) chosen = id;
  }
  if (chosen.empty()) {
    const std::vector<std::string> found = list_devices();
    throw CameraUnavailable("camera '" + (options_.id.empty() ? std::string("<first found>") : options_.id) +
                            "' (config key " + kSection + "id) not found; cameras visible: " +
                            (found.empty() ? std::string("none") : join(found)));
  }
  GError* error = nullptr;
  camera_ = arv_camera_new(chosen.c_str(), &error);
  if (camera_ == nullptr) throw_gerror(error, "cannot open camera '" + chosen + "'");
  control_lost_handler_ = g_signal_connect(arv_camera_get_device(camera_), "control-lost",
                                           G_CALLBACK(on_control_lost), control_lost_.get());
  try {
    configure();
  } catch (...) {
    close();
    throw;
  }
}

AravisCamera::~AravisCamera() { close(); }

void AravisCamera::close() {
  if (camera_ != nullptr && acquiring_) {
    GError* error = nullptr;
    arv_camera_stop_acquisition(camera_, &error);  // the camera may be gone: nothing to do about it
    if (error != nullptr) g_error_free(error);
    acquiring_ = false;
  }
  if (stream_ != nullptr) {
    g_object_unref(stream_);
    stream_ = nullptr;
  }
  if (camera_ != nullptr) {
    if (control_lost_handler_ != 0) g_signal_handler_disconnect(arv_camera_get_device(camera_), control_lost_handler_);
    control_lost_handler_ = 0;
    // Unreferencing the camera leaves GigE control so another host can take it.
    g_object_unref(camera_);
    camera_ = nullptr;
  }
}

void AravisCamera::configure() {
  EffectiveCameraSettings& s = settings_;
  s = EffectiveCameraSettings{};
  GError* error = nullptr;
  auto check = [&](const std::string& what) {
    if (error != nullptr) throw_gerror(error, "camera '" + s.device_id + "': " + what);
  };
  auto available = [&](const char* feature) {
    const bool yes = arv_camera_is_feature_available(camera_, feature, &error);
    check(std::string("querying feature ") + feature);
    return yes;
  };
  // A missing feature: a warning when config lists it as optional, else an error.
  auto missing = [&](const std::string& feature, const std::string& key) {
    const std::string text = "camera '" + s.device_id + "' has no feature '" + feature + "' (config key " + kSection +
                             key + ")";
    if (!options_.is_optional(feature)) {
      throw CameraConfigError(text + "; list it in " + kSection + "optional_features to continue without it");
    }
    s.warnings.push_back(text + ": left unchanged");
  };
  auto str = [](const char* v) { return std::string(v != nullptr ? v : ""); };

  s.device_id = str(arv_camera_get_device_id(camera_, &error));
  check("reading DeviceID");
  s.serial = str(arv_camera_get_device_serial_number(camera_, &error));
  if (error != nullptr) g_clear_error(&error);  // optional on some cameras
  // The device that answers must be the one asked for: two devices sharing a
  // control address (seen with two fake cameras on one interface) would
  // otherwise hand us another camera's frames.
  // Aravis ids end in the serial number ("Vendor-Model-Serial"), so the
  // check needs the serial; cameras that do not report one are not checked.
  if (!options_.id.empty() && !s.serial.empty()) {
    const std::string& want = options_.id;
    auto ends_with = [](const std::string& a, const std::string& b) {
      return !b.empty() && a.size() >= b.size() && a.compare(a.size() - b.size(), b.size(), b) == 0;
    };
    const bool same = want == s.serial || want == s.device_id || ends_with(want, "-" + s.serial);
    if (!same) {
      throw std::runtime_error("camera '" + want + "' answered as device '" + s.device_id + "' (serial '" + s.serial +
                               "'): another device shares its address; not using it");
    }
  }
  s.vendor = str(arv_camera_get_vendor_name(camera_, &error));
  if (error != nullptr) g_clear_error(&error);
  s.model = str(arv_camera_get_model_name(camera_, &error));
  if (error != nullptr) g_clear_error(&error);

  // Stop anything a previous owner left running before changing the format.
  arv_camera_stop_acquisition(camera_, &error);
  if (error != nullptr) g_clear_error(&error);

  // Pixel format: must be one the camera offers.
  guint n_formats = 0;
  const char** formats = arv_camera_dup_available_pixel_formats_as_strings(camera_, &n_formats, &error);
  check("listing pixel formats");
  std::vector<std::string> offered;
  for (guint i = 0; i < n_formats; ++i) offered.push_back(str(formats[i]));
  g_free(formats);
  bool offers = false;
  for (const auto& f : offered) offers = offers || f == options_.pixel_format;
  if (!offers) {
    throw CameraConfigError("camera '" + s.device_id + "' does not offer pixel format '" + options_.pixel_format +
                            "' (config key " + kSection + "pixel_format); it offers: " + join(offered));
  }
  arv_camera_set_pixel_format_from_string(camera_, options_.pixel_format.c_str(), &error);
  check("setting PixelFormat " + options_.pixel_format);
  s.pixel_format = str(arv_camera_get_pixel_format_as_string(camera_, &error));
  check("reading PixelFormat");

  // Binning before the region: it changes the region's limits.
  if (options_.binning_x != 1 || options_.binning_y != 1 || available("BinningHorizontal")) {
    if (available("BinningHorizontal") && available("BinningVertical")) {
      arv_camera_set_binning(camera_, options_.binning_x, options_.binning_y, &error);
      check("setting binning");
    } else if (options_.binning_x != 1 || options_.binning_y != 1) {
      missing("BinningHorizontal", "binning");
    }
  }
  arv_camera_get_binning(camera_, &s.binning_x, &s.binning_y, &error);
  if (error != nullptr) {
    g_clear_error(&error);
    s.binning_x = s.binning_y = 1;
  }

  int x = 0, y = 0, w = 0, h = 0;
  arv_camera_get_region(camera_, &x, &y, &w, &h, &error);
  check("reading the region");
  const int want_w = options_.roi_width > 0 ? options_.roi_width : w;
  const int want_h = options_.roi_height > 0 ? options_.roi_height : h;
  arv_camera_set_region(camera_, options_.roi_x, options_.roi_y, want_w, want_h, &error);
  check("setting the region " + std::to_string(want_w) + "x" + std::to_string(want_h) + "+" +
        std::to_string(options_.roi_x) + "+" + std::to_string(options_.roi_y));
  arv_camera_get_region(camera_, &s.x, &s.y, &s.width, &s.height, &error);
  check("reading the region");

  // Exposure.
  if (options_.exposure_mode == "auto") {
    if (!arv_camera_is_exposure_auto_available(camera_, &error)) {
      if (error != nullptr) g_clear_error(&error);
      missing("ExposureAuto", "exposure.mode");
    } else {
      arv_camera_set_exposure_time_auto(camera_, ARV_AUTO_CONTINUOUS, &error);
      check("setting ExposureAuto Continuous");
      // SFNC names for the auto exposure limits; vendors differ, so optional.
      for (const auto& [feature, value] : {std::pair<const char*, double>{"AutoExposureTimeLowerLimit",
                                                                        options_.exposure_auto_min_us},
                                           {"AutoExposureTimeUpperLimit", options_.exposure_auto_max_us}}) {
        if (available(feature)) {
          arv_device_set_float_feature_value(arv_camera_get_device(camera_), feature, value, &error);
          check(std::string("setting ") + feature);
        } else {
          s.warnings.push_back(std::string("camera has no '") + feature + "': auto exposure limits left unchanged");
        }
      }
    }
  } else {
    if (arv_camera_is_exposure_auto_available(camera_, &error)) {
      arv_camera_set_exposure_time_auto(camera_, ARV_AUTO_OFF, &error);
      check("setting ExposureAuto Off");
    }
    if (error != nullptr) g_clear_error(&error);
    arv_camera_set_exposure_time(camera_, options_.exposure_us, &error);
    check("setting the exposure time");
  }
  s.exposure_mode = options_.exposure_mode;
  s.exposure_us = arv_camera_get_exposure_time(camera_, &error);
  check("reading the exposure time");

  if (arv_camera_is_gain_available(camera_, &error)) {
    arv_camera_set_gain(camera_, options_.gain_db, &error);
    check("setting the gain");
    s.gain_db = arv_camera_get_gain(camera_, &error);
    check("reading the gain");
  } else {
    if (error != nullptr) g_clear_error(&error);
    missing("Gain", "gain_db");
  }

  // Trigger.
  arv_camera_clear_triggers(camera_, &error);
  if (error != nullptr) g_clear_error(&error);
  if (options_.trigger_mode == "free_run") {
    if (arv_camera_is_frame_rate_available(camera_, &error)) {
      arv_camera_set_frame_rate(camera_, options_.frame_rate_hz, &error);
      check("setting the frame rate");
      s.frame_rate_hz = arv_camera_get_frame_rate(camera_, &error);
      check("reading the frame rate");
    } else {
      if (error != nullptr) g_clear_error(&error);
      missing("AcquisitionFrameRate", "frame_rate_hz");
    }
    s.trigger_mode = "free_run";
  } else {
    const std::string source = options_.trigger_mode == "software" ? "Software" : options_.trigger_line;
    guint n_sources = 0;
    const char** sources = arv_camera_dup_available_trigger_sources(camera_, &n_sources, &error);
    check("listing trigger sources");
    std::vector<std::string> offered_sources;
    for (guint i = 0; i < n_sources; ++i) offered_sources.push_back(str(sources[i]));
    g_free(sources);
    bool has_source = false;
    for (const auto& f : offered_sources) has_source = has_source || f == source;
    if (!has_source) {
      throw CameraConfigError("camera '" + s.device_id + "' has no trigger source '" + source + "' (config key " +
                              kSection + (options_.trigger_mode == "software" ? "trigger.mode" : "trigger.line") +
                              "); it offers: " + join(offered_sources));
    }
    // FrameStart trigger from the chosen source (arv_camera_set_trigger also
    // selects rising edge where the camera supports TriggerActivation).
    arv_camera_set_trigger(camera_, source.c_str(), &error);
    check("setting the trigger to " + source);
    if (options_.trigger_mode == "hardware") {
      if (available("TriggerActivation")) {
        arv_device_set_string_feature_value(arv_camera_get_device(camera_), "TriggerActivation",
                                            options_.trigger_activation.c_str(), &error);
        check("setting TriggerActivation " + options_.trigger_activation);
      } else {
        missing("TriggerActivation", "trigger.activation");
      }
      if (options_.trigger_debounce_us > 0) {
        if (available("LineDebouncerTime")) {
          ArvDevice* device = arv_camera_get_device(camera_);
          arv_device_set_string_feature_value(device, "LineSelector", options_.trigger_line.c_str(), &error);
          check("selecting line " + options_.trigger_line);
          arv_device_set_float_feature_value(device, "LineDebouncerTime", options_.trigger_debounce_us, &error);
          check("setting LineDebouncerTime");
        } else {
          missing("LineDebouncerTime", "trigger.debounce_us");
        }
      }
    }
    s.trigger_mode = options_.trigger_mode;
    s.trigger_source = str(arv_camera_get_trigger_source(camera_, &error));
    check("reading TriggerSource");
    s.frame_rate_hz = options_.trigger_mode == "software" ? options_.software_trigger_rate_hz : 0.0;
  }

  // GigE transport.
  if (arv_camera_is_gv_device(camera_)) {
    if (options_.packet_size > 0) {
      arv_camera_gv_set_packet_size(camera_, options_.packet_size, &error);
      check("setting the GigE packet size");
    } else {
      arv_camera_gv_auto_packet_size(camera_, &error);
      if (error != nullptr) {
        s.warnings.push_back(std::string("packet size negotiation failed: ") + error->message);
        g_clear_error(&error);
      }
    }
    arv_camera_gv_set_packet_delay(camera_, options_.packet_delay_ns, &error);
    if (error != nullptr) {
      if (options_.packet_delay_ns > 0) check("setting the GigE inter-packet delay");
      g_clear_error(&error);
    }
    s.packet_size = arv_camera_gv_get_packet_size(camera_, &error);
    check("reading the GigE packet size");
    s.packet_delay_ns = static_cast<double>(arv_camera_gv_get_packet_delay(camera_, &error));
    if (error != nullptr) g_clear_error(&error);
  }
  s.payload_bytes = static_cast<int>(arv_camera_get_payload(camera_, &error));
  check("reading PayloadSize");
}

void AravisCamera::start() {
  GError* error = nullptr;
  arv_camera_set_acquisition_mode(camera_, ARV_ACQUISITION_MODE_CONTINUOUS, &error);
  if (error != nullptr) throw_gerror(error, "camera '" + settings_.device_id + "': setting AcquisitionMode");
  stream_ = arv_camera_create_stream(camera_, nullptr, nullptr, &error);
  if (stream_ == nullptr) throw_gerror(error, "camera '" + settings_.device_id + "': creating the stream");
  for (int i = 0; i < options_.stream_buffers; ++i) {
    arv_stream_push_buffer(stream_, arv_buffer_new_allocate(static_cast<size_t>(settings_.payload_bytes)));
  }
  arv_camera_start_acquisition(camera_, &error);
  if (error != nullptr) throw_gerror(error, "camera '" + settings_.device_id + "': starting acquisition");
  acquiring_ = true;
}

ArvBuffer* AravisCamera::pop(uint64_t timeout_us) {
  if (stream_ == nullptr) return nullptr;
  return arv_stream_timeout_pop_buffer(stream_, timeout_us);
}

void AravisCamera::requeue(ArvBuffer* buffer) { arv_stream_push_buffer(stream_, buffer); }

void AravisCamera::software_trigger() {
  GError* error = nullptr;
  arv_camera_software_trigger(camera_, &error);
  if (error != nullptr) {
    const std::string message = std::string("camera '") + settings_.device_id + "': software trigger failed: " +
                                error->message;
    g_error_free(error);
    throw CameraUnavailable(message);
  }
}

StreamStatistics AravisCamera::statistics() const {
  StreamStatistics stats;
  if (stream_ == nullptr) return stats;
  guint64 completed = 0, failures = 0, underruns = 0;
  arv_stream_get_statistics(stream_, &completed, &failures, &underruns);
  stats.completed = completed;
  stats.failures = failures;
  stats.underruns = underruns;
  return stats;
}

std::string EffectiveCameraSettings::to_yaml() const {
  std::ostringstream out;
  out << "device_id: \"" << device_id << "\"\n"
      << "serial: \"" << serial << "\"\n"
      << "vendor: \"" << vendor << "\"\n"
      << "model: \"" << model << "\"\n"
      << "pixel_format: " << pixel_format << "\n"
      << "roi: {x: " << x << ", y: " << y << ", width: " << width << ", height: " << height << "}\n"
      << "binning: [" << binning_x << ", " << binning_y << "]\n"
      << "exposure_mode: " << exposure_mode << "\n"
      << "exposure_us: " << exposure_us << "\n"
      << "gain_db: " << gain_db << "\n"
      << "frame_rate_hz: " << frame_rate_hz << "\n"
      << "trigger_mode: " << trigger_mode << "\n"
      << "trigger_source: \"" << trigger_source << "\"\n"
      << "packet_size: " << packet_size << "\n"
      << "packet_delay_ns: " << packet_delay_ns << "\n"
      << "payload_bytes: " << payload_bytes << "\n"
      << "warnings: [";
  for (size_t i = 0; i < warnings.size(); ++i) out << (i ? ", " : "") << "\"" << warnings[i] << "\"";
  out << "]\n";
  return out.str();
}

}  // namespace nadir
