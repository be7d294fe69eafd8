#include "processes/camera_capture/fake_gige_camera.h"

#include <arv.h>

#include <stdexcept>

namespace nadir {

struct FakeGigECamera::FillContext {
  ArvFakeCamera* camera;
  FrameSource* source;
};

namespace {

void fill_pattern(ArvBuffer* buffer, void* data, guint32, guint32, ArvPixelFormat) {
  const auto* context = static_cast<const FakeGigECamera::FillContext*>(data);
  FrameSource* source = context->source;
  // arv_buffer_get_data reports the received size, which is still 0 here;
  // the buffer holds the camera's payload.
  auto* pixels = static_cast<uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, nullptr)));
  const size_t size = arv_fake_camera_get_payload(context->camera);
  // The buffer's image geometry is not filled in yet when the callback runs:
  // the camera's registers say what it is sending.
  guint32 w = 0, h = 0;
  arv_fake_camera_read_register(context->camera, ARV_FAKE_CAMERA_REGISTER_WIDTH, &w);
  arv_fake_camera_read_register(context->camera, ARV_FAKE_CAMERA_REGISTER_HEIGHT, &h);
  const int width = static_cast<int>(w);
  const int height = static_cast<int>(h);
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
  context_ = std::make_unique<FillContext>(FillContext{fake, source_.get()});
  arv_fake_camera_set_fill_pattern(fake, fill_pattern, context_.get());
  arv_fake_camera_set_trigger_frequency(fake, options_.trigger_poll_hz);
}

void FakeGigECamera::trigger() {
  arv_fake_camera_write_register(arv_gv_fake_camera_get_fake_camera(camera_),
                                 ARV_FAKE_CAMERA_REGISTER_FRAME_START_OFFSET + ARV_FAKE_CAMERA_REGISTER_TRIGGER_SOFTWARE,
                                 1);
}

FakeGigECamera::~FakeGigECamera() {
  if (camera_ != nullptr) g_object_unref(camera_);  // stops its thread and closes its sockets
}

}  // namespace nadir
