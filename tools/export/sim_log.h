#pragma once
// What the exporter needs from a nadir_sim log: the camera (CONFIG's camera:
// section), every CAMERA_IMAGE (decoded on demand: a flight's images do not
// fit comfortably in memory), INS, ALTIMETER and the per-frame GROUND_TRUTH.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/camera_model.h"
#include "common/log_file.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"

namespace nadir::exporter {

struct SimImageRef {
  int64_t utime = 0;          // sensor time (the reported exposure time)
  int64_t frame_counter = 0;
  const uint8_t* data = nullptr;  // encoded image_t, valid while the SimLog lives
  size_t size = 0;
  uint64_t offset = 0;        // byte offset of its record, for errors
};

class SimLog {
 public:
  // Reads `path`; throws std::runtime_error naming the file (and byte offset)
  // when it is not a nadir_sim log: no CONFIG from the simulator, no camera
  // section, a message that does not decode, no images, no INS or truth.
  static std::unique_ptr<SimLog> load(const std::string& path);

  const std::string& path() const { return path_; }
  const CameraModel& camera() const { return camera_; }
  const std::vector<SimImageRef>& images() const { return images_; }
  const std::vector<ins_t>& ins() const { return ins_; }                  // sorted by utime
  const std::vector<altimeter_t>& altimeter() const { return altimeter_; }  // sorted by utime
  const std::vector<ground_truth_t>& frame_truth() const { return frame_truth_; }  // KIND_FRAME, sorted

  // Decodes one image; throws naming the file and offset.
  image_t decode_image(const SimImageRef& ref) const;
  // GROUND_TRUTH (KIND_FRAME) of the frame stamped `image_utime`: the truth
  // nearest in time, which lies within the trigger jitter (a quarter frame
  // period at most). Throws when there is none that close.
  const ground_truth_t& truth_for_frame(int64_t image_utime) const;
  // Index of the INS sample nearest to `utime`.
  size_t nearest_ins(int64_t utime) const;
  // INS lat/lon/height linearly interpolated to `utime` (clamped at the ends).
  void ins_position_at(int64_t utime, double* lat_deg, double* lon_deg, double* height_m) const;
  // Heading rate (rad/s) from the INS's body rates at the sample nearest `utime`.
  double yaw_rate_at(int64_t utime) const;
  // The valid altimeter range nearest in time to `utime` (either side);
  // false if none lies within `max_age_us`.
  bool range_near(int64_t utime, int64_t max_age_us, double* range_m) const;

 private:
  explicit SimLog(const std::string& path) : path_(path), reader_(path) {}
  std::string path_;
  LogReader reader_;  // maps the file: SimImageRef::data points into it
  CameraModel camera_;
  std::vector<SimImageRef> images_;
  std::vector<ins_t> ins_;
  std::vector<altimeter_t> altimeter_;
  std::vector<ground_truth_t> frame_truth_;
};

}  // namespace nadir::exporter
