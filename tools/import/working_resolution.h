#pragma once
// The resolution an import brings its images to. The tracker is tuned for
// images of a few hundred pixels across (the live camera is 612x512): larger
// images solve no more pairs (fewer on a real 12 MP survey) and SIFT's time
// and memory grow with the pixel count (20 photos of 12 MP: 94 s, 2.9 GB).
// Rule (docs/own-flight.md, "The working resolution"; the measurement:
// docs/research/2026-12-photo-resolution.md): without --scale, the image is
// shrunk by the smallest whole factor k that brings its long side to at most
// kWorkingLongSidePx (scale 1/k; never up). --scale S overrides it (1: full size).

#include <string>

namespace nadir::import {

inline constexpr int kWorkingLongSidePx = 1000;

struct WorkingResolution {
  double scale = 1.0;     // the images (and the intrinsics) are scaled by this
  int width = 0, height = 0;  // the images' size after scaling
  std::string rule;       // the scale and how it was chosen: "1/4: long side 4000 px over 1000 px", "0.5: --scale"
};

// `requested` > 0: that scale (--scale); 0: the rule above. Sizes round as
// CameraIntrinsics::scaled does.
WorkingResolution working_resolution(int width, int height, double requested);

// "working resolution WxH (scale RULE)"
std::string describe(const WorkingResolution& r);

}  // namespace nadir::import
