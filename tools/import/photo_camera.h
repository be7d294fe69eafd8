#pragma once
// The camera from what a photo file says, when no calibration is given:
//  0. DJI XMP drone-dji:DewarpData (fx, fy, principal point from the photo's
//     centre, k1 k2 p1 p2 k3: the lens distortion too) unless DewarpFlag says
//     the image was already dewarped, scaled like (1);
//  1. DJI XMP drone-dji:CalibratedFocalLength (+ CalibratedOpticalCenterX/Y),
//     in pixels of the image as the camera wrote it (EXIF PixelXDimension),
//     scaled to the file's size when the file was resized;
//  2. else EXIF FocalLengthIn35mmFilm referred to the sensor's native frame:
//     the 35 mm equivalent is defined on the diagonal of the sensor's full
//     frame (36x24 mm film: 43.27 mm), so a photo cropped from the sensor
//     (16:9 from a 4:3 sensor) takes the diagonal of the native frame at the
//     photo's scale, not its own. The native aspect comes from the camera
//     table (camera_table.h) by EXIF Model; an unknown model's photo is taken
//     as the full frame;
//  3. else an error naming the file, the model, how to give the focal length
//     and what the camera table knows of the model.
// Docs: docs/own-flight.md, "The camera from the photos".

#include <cmath>
#include <string>
#include <vector>

#include "tools/import/photo_metadata.h"

namespace nadir::import {

struct PhotoFocal {
  double focal_px = 0;                // fx, at the file's size
  double fy = 0;                      // 0: fy = fx
  std::vector<double> distortion;     // k1 k2 p1 p2 k3 (empty: none known)
  bool has_center = false;            // false: the image centre
  double cx = 0, cy = 0;              // pixel-centre coordinates, at the file's size
  std::string source;                 // "XMP drone-dji:DewarpData" | "XMP drone-dji:CalibratedFocalLength" | "EXIF FocalLengthIn35mmFilm"
  std::string rule;                   // how the number was made, one line
  std::string warning;                // one line naming the model and what was assumed
};

// Focal length of a `width` x `height` photo from its metadata `m`; throws
// std::runtime_error naming the file when the metadata gives none.
PhotoFocal focal_from_photo(const PhotoMetadata& m, int width, int height);

// Diagonal in pixels of the sensor's native frame (aspect `native_width` :
// `native_height`) that a `width` x `height` photo is a crop of, at the
// photo's scale: the side the crop kept is the native frame's side.
double native_frame_diagonal_px(int width, int height, int native_width, int native_height);

// The diagonal of 35 mm film's 36x24 mm frame (43.27 mm).
inline const double kFullFrameDiagonalMm = std::hypot(36.0, 24.0);

}  // namespace nadir::import
