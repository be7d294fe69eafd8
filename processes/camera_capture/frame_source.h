#pragma once
// Image content for the fake GigE camera: a synthetic pattern (tests choose
// and check it) or the CAMERA_IMAGE frames of a recorded or simulated log.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace nadir {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Writes a width x height Mono8 image (rows `stride` bytes apart) for the
  // camera's frame `frame_id`. Called from the fake camera's thread.
  virtual void fill(uint64_t frame_id, int width, int height, size_t stride, uint8_t* pixels) = 0;
  virtual std::string describe() const = 0;
};

// value(x, y, frame) = (x + 2 y + 3 frame) mod 256: every pixel and every
// frame differ, so a test can check both content and frame identity.
class PatternFrameSource : public FrameSource {
 public:
  static uint8_t value(int x, int y, uint64_t frame_id) {
    return static_cast<uint8_t>((static_cast<uint64_t>(x) + 2u * static_cast<uint64_t>(y) + 3u * frame_id) & 0xffu);
  }
  void fill(uint64_t frame_id, int width, int height, size_t stride, uint8_t* pixels) override;
  std::string describe() const override { return "pattern (x + 2y + 3 frame) mod 256"; }
};

// Serves the CAMERA_IMAGE frames of an LCM log in order, one per camera
// frame, looping at the end. Frames larger than the camera's region are
// cropped, smaller ones padded with black; Mono16 is reduced to its high byte.
class LogFrameSource : public FrameSource {
 public:
  // Reads all frames up front (a 60 s flight at 14 Hz, 612x512 Mono8, is
  // about 260 MB; max_frames bounds it). Throws std::runtime_error naming the
  // file when it has no usable CAMERA_IMAGE frame.
  LogFrameSource(const std::string& path, const std::string& channel, size_t max_frames);
  void fill(uint64_t frame_id, int width, int height, size_t stride, uint8_t* pixels) override;
  std::string describe() const override;
  size_t frames() const { return frames_.size(); }
  // Paced serving: the next fills show frame i (set before triggering it),
  // so fills that are not frames (GigE packet-size test packets) cannot
  // shift the sequence. Thread-safe.
  void select(size_t i) { selected_.store(static_cast<int64_t>(i % frames_.size())); }
  // Sensor time (image_t.utime) of frame i in the log.
  int64_t frame_utime(size_t i) const { return frames_[i].utime; }
  int64_t skipped() const { return skipped_; }

 private:
  struct Frame {
    int width = 0, height = 0;
    int64_t utime = 0;
    std::vector<uint8_t> mono8;
  };
  std::string path_;
  std::vector<Frame> frames_;
  int64_t skipped_ = 0;
  uint64_t served_ = 0;
  std::atomic<int64_t> selected_{-1};
};

}  // namespace nadir
