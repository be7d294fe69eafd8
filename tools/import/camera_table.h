#pragma once
// Native sensor geometry of common survey cameras, keyed by the EXIF Model
// string the camera writes. The importer needs a camera's native aspect ratio
// to refer a 35 mm equivalent focal length to the sensor's full frame when a
// photo is a crop of it (a 16:9 photo from a 4:3 sensor); the rest of a row
// is what the import's messages quote. Every row names its source; numbers a
// manufacturer does not state are marked as such in the row's note.

#include <string>
#include <vector>

namespace nadir::import {

struct KnownCamera {
  std::vector<std::string> models;  // EXIF Exif.Image.Model as written (compared ignoring case)
  std::string name;                 // aircraft / camera, for messages
  double sensor_width_mm = 0, sensor_height_mm = 0;
  int native_width = 0, native_height = 0;  // full-frame photo in pixels (landscape)
  double focal_mm = 0;              // nominal lens focal length
  double focal_35mm = 0;            // nominal 35 mm equivalent (diagonal), 0 when not stated
  std::string source;               // where the numbers come from, and which are uncertain
};

// Every row, in table order.
const std::vector<KnownCamera>& known_cameras();

// The row for `model` (trimmed, any case); when a model names several
// cameras (a wide and a thermal camera writing the same Model), the one whose
// native size is nearest the photo's `width` x `height`. nullptr if unknown.
const KnownCamera* find_known_camera(const std::string& model, int width, int height);

}  // namespace nadir::import
