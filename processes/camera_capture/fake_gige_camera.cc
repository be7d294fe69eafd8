#include "processes/camera_capture/fake_gige_camera.h"

#include <arv.h>

#include <stdexcept>

namespace nadir {

namespace {

void fill_pattern(ArvBuffer* buffer, void* data, guint32, guint32, ArvPixelFormat) {
  auto* source = static_cast<FrameSource*>(data);
  size_t size = 0;
  auto* pixels = static_cast<uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, &size)));
  const int width = arv_buffer_get_image_width(buffer);
  const int height = arv_buffer_get_image_height(buffer);
  if (pixels == nullptr || width <= 0 || height <= 0 || size < static_cast<size_t>(width) * height) return;
  source->fill(arv_buffer_get_frame_id(buffer), width, height, static_cast<size_t>(width), pixels);
}

}  // namespace

FakeGigECamera::FakeGigECamera(const FakeCameraOptions& options, std::shared_ptr<FrameSource> source)
    : options_(options), source_(std::move(source)) {
  camera_ = arv_gv_fake_camera_new(options_.interface_name.c_str(), options_.serial.c_str());
  if (camera_ == nullptr || !arv_gv_fake_camera_is_running(camera_)) {
    if (camera_ != nullptr) g_object_unref(camera_);
    throw std::runtime_error("fake GigE camera cannot listen on interface '" + options_.interface_name +
                             "' (is it up, and is the GVCP port 3956 free?)");
  }
  ArvFakeCamera* fake = arv_gv_fake_camera_get_fake_camera(camera_);
  arv_fake_camera_set_fill_pattern(fake, fill_pattern, source_.get());
  arv_fake_camera_set_trigger_frequency(fake, options_.trigger_poll_hz);
}

FakeGigECamera::~FakeGigECamera() {
  if (camera_ != nullptr) g_object_unref(camera_);  // stops its thread and closes its sockets
}

}  // namespace nadir
