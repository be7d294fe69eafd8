// Config of the capture: defaults from config/default.yaml, and clear errors
// naming the key for values nadir or the camera cannot use.

#include "processes/camera_capture/capture_options.h"

#include <gtest/gtest.h>

#include <string>

namespace nadir {
namespace {

std::string error_of(const std::string& yaml) {
  try {
    CaptureOptions::FromConfig(Config::parse(yaml, "bad.yaml"));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(CaptureOptions, DefaultConfigFileLoads) {
  const Config root = Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
  const CaptureOptions o = CaptureOptions::FromConfig(root.section_or_empty("camera_capture"));
  EXPECT_EQ(o.camera.pixel_format, "Mono8");
  EXPECT_EQ(o.camera.roi_width, 612);
  EXPECT_EQ(o.camera.roi_height, 512);
  EXPECT_DOUBLE_EQ(o.camera.frame_rate_hz, 14.0);
}

TEST(CaptureOptions, UnsupportedPixelFormatNamesTheKey) {
  const std::string e = error_of("camera: {pixel_format: RGB8}\n");
  EXPECT_NE(e.find("pixel_format"), std::string::npos) << e;
  EXPECT_NE(e.find("RGB8"), std::string::npos) << e;
  EXPECT_NE(e.find("bad.yaml"), std::string::npos) << e;
}

TEST(CaptureOptions, BadValuesNameTheirKeys) {
  EXPECT_NE(error_of("camera: {trigger: {mode: sometimes}}\n").find("trigger.mode"), std::string::npos);
  EXPECT_NE(error_of("trigger_input: {source: serial}\n").find("trigger_input.source"), std::string::npos);
  EXPECT_NE(error_of("unassociated_frames: keep\n").find("unassociated_frames"), std::string::npos);
  EXPECT_NE(error_of("camera: {stream_buffers: 1}\n").find("stream_buffers"), std::string::npos);
  EXPECT_NE(error_of("association: {offset_tolerance_us: 0}\n").find("association.offset_tolerance_us"),
            std::string::npos);
  EXPECT_NE(error_of("camera: {binning: [1]}\n").find("binning"), std::string::npos);
}

}  // namespace
}  // namespace nadir
