#include "processes/camera_capture/camera_capture.h"

#include <arv.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "common/channels.h"
#include "common/time_base.h"
#include "nadir/image_t.hpp"
#include "nadir/trigger_t.hpp"
#include "processes/camera_capture/image_time.h"

namespace nadir {

namespace {

// GenICam names a Bayer pattern by its first row; OpenCV by the second
// row's last two pixels, so the names are swapped pairwise.
int bayer_to_gray_code(ArvPixelFormat format) {
  switch (format) {
    case ARV_PIXEL_FORMAT_BAYER_RG_8: return cv::COLOR_BayerBG2GRAY;
    case ARV_PIXEL_FORMAT_BAYER_GR_8: return cv::COLOR_BayerGB2GRAY;
    case ARV_PIXEL_FORMAT_BAYER_GB_8: return cv::COLOR_BayerGR2GRAY;
    case ARV_PIXEL_FORMAT_BAYER_BG_8: return cv::COLOR_BayerRG2GRAY;
    default: return -1;
  }
}

}  // namespace

CameraCapture::CameraCapture(const CaptureOptions& options, Bus& bus, std::unique_ptr<TriggerSource> trigger)
    : options_(options),
      bus_(bus),
      trigger_(std::move(trigger)),
      associator_(options.association),
      clock_(std::make_unique<ClockSync>(options.clock_sync)) {
  options_.Check();
  backoff_s_ = options_.reconnect_initial_backoff_s;
}

CameraCapture::~CameraCapture() { stop(); }

void CameraCapture::connect() {
  try {
    auto camera = std::make_unique<AravisCamera>(options_.camera);
    camera->start();
    camera_ = std::move(camera);
  } catch (const std::exception& e) {
    last_error_ = e.what();
    next_attempt_mono_us_ = monotonic_now_us() + s_to_us(backoff_s_);
    backoff_s_ = std::min(backoff_s_ * 2, options_.reconnect_max_backoff_s);
    ++reconnect_attempts_;
    throw;
  }
  settings_ = camera_->settings();
  stopped_ = false;
  if (ever_connected_) ++reconnects_;
  ever_connected_ = true;
  backoff_s_ = options_.reconnect_initial_backoff_s;
  reconnect_attempts_ = 0;
  last_error_.clear();
  disconnect_reason_.clear();
  // A new camera session: its clock and frame counter start over.
  clock_ = std::make_unique<ClockSync>(options_.clock_sync);
  associator_.reset_lock("camera (re)connected");
  frame_due_since_mono_us_ = options_.camera.trigger_mode == "free_run" ? monotonic_now_us() : -1;
  next_software_trigger_mono_us_ = monotonic_now_us();
  if (on_connected_) on_connected_(settings_);
}

void CameraCapture::stop() {
  stopped_ = true;
  if (camera_ == nullptr) return;
  publish_decisions(associator_.decide(std::numeric_limits<int64_t>::max() / 2));
  for (auto& [token, buffer] : held_) g_object_unref(buffer);
  held_.clear();
  const StreamStatistics s = camera_->statistics();
  stats_before_.completed += s.completed;
  stats_before_.failures += s.failures;
  stats_before_.underruns += s.underruns;
  camera_.reset();
}

void CameraCapture::disconnect(const std::string& why) {
  disconnect_reason_ = why;
  ++disconnects_;
  stop();
  stopped_ = false;
  next_attempt_mono_us_ = monotonic_now_us() + s_to_us(backoff_s_);
}

void CameraCapture::try_reconnect(int64_t now_mono_us) {
  if (now_mono_us < next_attempt_mono_us_) return;
  try {
    connect();
  } catch (const std::exception&) {
    // connect() recorded the error and scheduled the next attempt.
  }
}

void CameraCapture::handle_edges(const std::vector<TriggerEdge>& edges) {
  for (const TriggerEdge& edge : edges) {
    ++edges_received_;
    const bool accepted = associator_.add_edge(edge);
    trigger_t msg{};
    msg.utime = edge.vehicle_us;
    msg.device_utime = edge.device_us;
    msg.sequence = edge.sequence;
    msg.edge = edge.edge;
    msg.flags = accepted ? 0 : trigger_t::FLAG_SPURIOUS;
    bus_.publish(channels::kCameraTrigger, msg);
    ++published_triggers_;
    if (accepted && camera_ != nullptr && frame_due_since_mono_us_ < 0) frame_due_since_mono_us_ = monotonic_now_us();
  }
}

void CameraCapture::release(ArvBuffer* buffer) {
  if (camera_ != nullptr) {
    camera_->requeue(buffer);
  } else {
    g_object_unref(buffer);
  }
}

void CameraCapture::publish_image(ArvBuffer* buffer, int64_t utime, int64_t trigger_utime, int64_t trigger_sequence,
                                  int8_t time_quality) {
  size_t size = 0;
  const uint8_t* pixels = static_cast<const uint8_t*>(arv_buffer_get_image_data(buffer, &size));
  const ArvPixelFormat format = arv_buffer_get_image_pixel_format(buffer);
  const int width = arv_buffer_get_image_width(buffer);
  const int height = arv_buffer_get_image_height(buffer);
  const int bayer = bayer_to_gray_code(format);
  const bool wide = format == ARV_PIXEL_FORMAT_MONO_16 || format == ARV_PIXEL_FORMAT_MONO_12 ||
                    format == ARV_PIXEL_FORMAT_MONO_10;
  const int bytes_per_pixel = wide ? 2 : 1;
  const size_t out_size = static_cast<size_t>(width) * height * bytes_per_pixel;
  if (pixels == nullptr || size < out_size || (!wide && format != ARV_PIXEL_FORMAT_MONO_8 && bayer < 0)) {
    ++buffers_incomplete_;
    last_error_ = "frame " + std::to_string(arv_buffer_get_frame_id(buffer)) + ": unusable pixel format 0x" +
                  std::to_string(format) + " or size " + std::to_string(size);
    return;
  }
  image_t header{};
  header.utime = utime;
  header.trigger_utime = trigger_utime;
  header.frame_counter = static_cast<int64_t>(arv_buffer_get_frame_id(buffer));
  header.trigger_sequence = trigger_sequence;
  header.width = width;
  header.height = height;
  header.stride = width * bytes_per_pixel;
  header.pixel_format = wide ? image_t::PIXEL_MONO16 : image_t::PIXEL_MONO8;
  header.time_quality = time_quality;
  header.exposure_us = static_cast<float>(settings_.exposure_us);
  header.gain_db = static_cast<float>(settings_.gain_db);
  uint8_t* out = encoder_.begin(header, out_size);
  if (bayer >= 0) {
    const cv::Mat raw(height, width, CV_8UC1, const_cast<uint8_t*>(pixels));
    cv::Mat gray(height, width, CV_8UC1, out);
    cv::cvtColor(raw, gray, bayer);  // writes into the message: still one pass over the pixels
  } else {
    std::memcpy(out, pixels, out_size);
  }
  bus_.publish_raw(channels::kCameraImage, encoder_.data(), encoder_.size());
  ++published_images_;
  if (time_quality == image_t::TIME_TRIGGER) ++frames_trigger_time_;
  if (time_quality == image_t::TIME_CAMERA_CLOCK) ++frames_camera_clock_;
  if (time_quality == image_t::TIME_ARRIVAL) ++frames_arrival_time_;
}

void CameraCapture::handle_buffer(ArvBuffer* buffer) {
  ++buffers_received_;
  if (arv_buffer_get_status(buffer) != ARV_BUFFER_STATUS_SUCCESS) {
    ++buffers_incomplete_;
    release(buffer);
    return;
  }
  frame_due_since_mono_us_ = options_.camera.trigger_mode == "free_run" ? monotonic_now_us() : -1;
  // The stream thread stamps the host (CLOCK_REALTIME = vehicle time) when
  // the frame's first packet arrives: a better arrival time than ours.
  const uint64_t system_ns = arv_buffer_get_system_timestamp(buffer);
  const int64_t arrival_us = system_ns > 0 ? static_cast<int64_t>(system_ns / 1000) : vehicle_time_now_us();
  const int64_t camera_us = static_cast<int64_t>(arv_buffer_get_timestamp(buffer) / 1000);
  const double exposure = settings_.exposure_us;
  if (camera_us != 0) clock_->add(camera_us, arrival_us);

  if (trigger_ == nullptr) {
    // No GPIO: camera clock mapped by the offset/drift estimator.
    if (camera_us != 0 && clock_->valid()) {
      const int64_t utime = utime_from_camera_clock(options_.timing, *clock_, camera_us, exposure);
      publish_image(buffer, utime, clock_->to_vehicle(camera_us), -1, image_t::TIME_CAMERA_CLOCK);
    } else {
      publish_image(buffer, mid_exposure_utime(arrival_us, exposure), arrival_us, -1, image_t::TIME_ARRIVAL);
    }
    release(buffer);
    return;
  }
  FrameStamp stamp;
  stamp.token = next_token_++;
  stamp.frame_counter = static_cast<int64_t>(arv_buffer_get_frame_id(buffer));
  stamp.camera_us = camera_us;
  stamp.arrival_us = arrival_us;
  held_[stamp.token] = buffer;
  associator_.add_frame(stamp);
}

void CameraCapture::publish_decisions(std::vector<AssociationDecision> decisions) {
  for (const AssociationDecision& d : decisions) {
    auto it = held_.find(d.frame.token);
    if (it == held_.end()) continue;
    ArvBuffer* buffer = it->second;
    held_.erase(it);
    const double exposure = settings_.exposure_us;
    switch (d.result) {
      case AssociationResult::kMatched:
        publish_image(buffer, utime_from_trigger(options_.timing, d.edge.vehicle_us, exposure), d.edge.vehicle_us,
                      d.edge.sequence, image_t::TIME_TRIGGER);
        break;
      case AssociationResult::kEstimatedFromLock:
        if (options_.publish_unassociated) {
          publish_image(buffer, utime_from_trigger(options_.timing, d.edge_estimate_us, exposure),
                        d.edge_estimate_us, -1, image_t::TIME_CAMERA_CLOCK);
        } else {
          ++dropped_unassociated_;
        }
        break;
      case AssociationResult::kUnmatched:
        if (!options_.publish_unassociated) {
          ++dropped_unassociated_;
        } else if (d.frame.camera_us != 0 && clock_->valid()) {
          publish_image(buffer, utime_from_camera_clock(options_.timing, *clock_, d.frame.camera_us, exposure),
                        clock_->to_vehicle(d.frame.camera_us), -1, image_t::TIME_CAMERA_CLOCK);
        } else {
          publish_image(buffer, mid_exposure_utime(d.frame.arrival_us, exposure), d.frame.arrival_us, -1,
                        image_t::TIME_ARRIVAL);
        }
        break;
    }
    release(buffer);
  }
}

void CameraCapture::step(int max_wait_ms) {
  const int64_t start_mono = monotonic_now_us();
  std::vector<TriggerEdge> edges;
  if (camera_ == nullptr) {
    // Edges keep coming while the camera is away: publish them anyway.
    if (trigger_ != nullptr) {
      trigger_->poll(std::max(1, max_wait_ms / 2), &edges);
      handle_edges(edges);
    }
    try_reconnect(monotonic_now_us());
    if (camera_ == nullptr) {
      const int64_t left_us = std::max<int64_t>(0, start_mono + int64_t(max_wait_ms) * 1000 - monotonic_now_us());
      const int64_t until_attempt = std::max<int64_t>(0, next_attempt_mono_us_ - monotonic_now_us());
      g_usleep(static_cast<gulong>(std::min(left_us, until_attempt)));
      software_requests_.store(0);  // triggers asked for while the camera was away are void
      return;
    }
  }

  if (trigger_ != nullptr) {
    trigger_->poll(0, &edges);
    handle_edges(edges);
  }

  // Software triggers: on request (tests, HIL) or on the configured schedule.
  if (options_.camera.trigger_mode == "software") {
    int requests = static_cast<int>(software_requests_.exchange(0));
    const double rate = options_.camera.software_trigger_rate_hz;
    if (rate > 0 && monotonic_now_us() >= next_software_trigger_mono_us_) {
      ++requests;
      next_software_trigger_mono_us_ += static_cast<int64_t>(1e6 / rate);
      if (next_software_trigger_mono_us_ < monotonic_now_us()) next_software_trigger_mono_us_ = monotonic_now_us();
    }
    for (int i = 0; i < requests && camera_ != nullptr; ++i) {
      if (trigger_hook_) trigger_hook_(vehicle_time_now_us());
      try {
        camera_->software_trigger();
        ++software_triggers_sent_;
        if (frame_due_since_mono_us_ < 0) frame_due_since_mono_us_ = monotonic_now_us();
      } catch (const CameraUnavailable& e) {
        disconnect(e.what());
        return;
      }
    }
    if (trigger_ != nullptr && requests > 0) {
      edges.clear();
      trigger_->poll(0, &edges);
      handle_edges(edges);
    }
  }

  // Frames: wait for the first, then take whatever else is ready.
  int64_t wait_us = std::max<int64_t>(0, start_mono + int64_t(max_wait_ms) * 1000 - monotonic_now_us());
  if (options_.camera.trigger_mode == "software" && options_.camera.software_trigger_rate_hz > 0) {
    wait_us = std::min<int64_t>(wait_us, std::max<int64_t>(0, next_software_trigger_mono_us_ - monotonic_now_us()));
  }
  if (!held_.empty()) wait_us = std::min<int64_t>(wait_us, 2000);  // frames are waiting for edges
  ArvBuffer* buffer = camera_->pop(static_cast<uint64_t>(wait_us));
  while (buffer != nullptr) {
    handle_buffer(buffer);
    buffer = camera_->pop(0);
  }
  if (trigger_ != nullptr) {
    edges.clear();
    trigger_->poll(0, &edges);
    handle_edges(edges);
    publish_decisions(associator_.decide(vehicle_time_now_us()));
  }

  // Faults: the camera stopped answering, or frames stopped coming.
  if (camera_->control_lost()) {
    disconnect("camera '" + settings_.device_id + "' lost (control channel heartbeat failed)");
    return;
  }
  if (frame_due_since_mono_us_ >= 0 &&
      us_to_s(monotonic_now_us() - frame_due_since_mono_us_) > options_.frame_timeout_s) {
    disconnect("camera '" + settings_.device_id + "' sent no frame for " + std::to_string(options_.frame_timeout_s) +
               " s while one was due");
  }
}

StatusReport CameraCapture::status() const {
  StatusReport r;
  const AssociationCounters& a = associator_.counters();
  r.received = buffers_received_ + edges_received_;
  r.published = published_images_ + published_triggers_;
  r.dropped = buffers_incomplete_ + dropped_unassociated_ + a.frame_counter_gaps;
  StreamStatistics s = stats_before_;
  if (camera_ != nullptr) {
    const StreamStatistics now = camera_->statistics();
    s.completed += now.completed;
    s.failures += now.failures;
    s.underruns += now.underruns;
  }
  if (camera_ == nullptr && stopped_) {
    r.state = status_t::STATE_STOPPING;
    r.detail = "capture stopped, camera released";
  } else if (camera_ == nullptr) {
    r.state = status_t::STATE_ERROR;
    r.detail = (disconnect_reason_.empty() ? std::string("camera not connected") : disconnect_reason_) +
               "; reconnecting (attempt " + std::to_string(reconnect_attempts_) + ")" +
               (last_error_.empty() ? "" : ": " + last_error_);
  } else if (!settings_.warnings.empty()) {
    r.state = status_t::STATE_WARN;
    r.detail = settings_.warnings.front();
  } else if (!last_error_.empty()) {
    r.state = status_t::STATE_WARN;
    r.detail = last_error_;
  }
  r.counters = {{"connected", camera_ != nullptr ? 1.0 : 0.0},
                {"reconnects", double(reconnects_)},
                {"disconnects", double(disconnects_)},
                {"images_published", double(published_images_)},
                {"triggers_published", double(published_triggers_)},
                {"frames_time_trigger", double(frames_trigger_time_)},
                {"frames_time_camera_clock", double(frames_camera_clock_)},
                {"frames_time_arrival", double(frames_arrival_time_)},
                {"frames_dropped_unassociated", double(dropped_unassociated_)},
                {"buffers_received", double(buffers_received_)},
                {"buffers_incomplete", double(buffers_incomplete_)},
                {"software_triggers_sent", double(software_triggers_sent_)},
                {"stream_completed", double(s.completed)},
                {"stream_failures", double(s.failures)},
                {"stream_underruns", double(s.underruns)},
                {"clock_sync_valid", clock_->valid() ? 1.0 : 0.0},
                {"clock_offset_us", clock_->state().offset_us},
                {"clock_drift_ppm", clock_->state().drift_ppm},
                {"clock_jumps", double(clock_->state().jumps)},
                {"assoc_locked", associator_.locked() ? 1.0 : 0.0},
                {"assoc_locked_offset_us", associator_.locked_offset_us()}};
  for (const auto& c : a.as_list()) r.counters.push_back(c);
  return r;
}

}  // namespace nadir
