#include "tools/import/photo_camera.h"

#include <array>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "tools/import/camera_table.h"

namespace nadir::import {
namespace {

constexpr double kSameAspect = 0.01;  // relative: a frame this close to the native aspect is the full frame

std::string model_name(const PhotoMetadata& m) {
  if (m.model.empty()) return "(no EXIF Model)";
  return m.make.empty() ? "'" + m.model + "'" : "'" + m.model + "' (" + m.make + ")";
}

std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char text[160];
  std::snprintf(text, sizeof(text), fmt, a, b, c, d);
  return text;
}

}  // namespace

double native_frame_diagonal_px(int width, int height, int native_width, int native_height) {
  const double photo_long = std::max(width, height), photo_short = std::min(width, height);
  const double native_aspect = static_cast<double>(std::min(native_width, native_height)) /
                               std::max(native_width, native_height);  // short / long
  const double photo_aspect = photo_short / photo_long;
  if (std::fabs(photo_aspect / native_aspect - 1.0) <= kSameAspect) return std::hypot(photo_long, photo_short);
  if (photo_aspect < native_aspect) {
    // wider than the sensor (16:9 from 4:3): the long side is the sensor's
    return photo_long * std::hypot(1.0, native_aspect);
  }
  // squarer than the sensor (1:1 from 4:3): the short side is the sensor's
  return photo_short * std::hypot(1.0, 1.0 / native_aspect);
}

PhotoFocal focal_from_photo(const PhotoMetadata& m, int width, int height) {
  const KnownCamera* known = find_known_camera(m.model, width, height);
  PhotoFocal f;
  // DJI's calibration is for the image the camera wrote; a resized file
  // (long side changed) scales it, pixel centres kept.
  const int written_long = std::max(m.exif_width, m.exif_height);
  const double s = written_long > 0 ? static_cast<double>(std::max(width, height)) / written_long : 1.0;
  if (m.has_dji_dewarp && m.dji_dewarp_flag != 1) {
    // cx, cy from the photo's centre, taken as the centre of the pixel grid
    // ((W - 1) / 2 in pixel-centre coordinates) of the image the camera wrote.
    const std::array<double, 9>& d = m.dji_dewarp;
    const double written_w = m.exif_width > 0 ? m.exif_width : width / s;
    const double written_h = m.exif_height > 0 ? m.exif_height : height / s;
    f.focal_px = d[0] * s;
    f.fy = d[1] * s;
    f.has_center = true;
    f.cx = (0.5 * (written_w - 1.0) + d[2] + 0.5) * s - 0.5;
    f.cy = (0.5 * (written_h - 1.0) + d[3] + 0.5) * s - 0.5;
    f.distortion.assign(d.begin() + 4, d.end());
    f.source = "XMP drone-dji:DewarpData";
    f.rule = format("DJI's lens calibration: fx %.2f, fy %.2f px, centre %+.2f, %+.2f px from the photo's centre",
                    d[0], d[1], d[2], d[3]) +
             format("; k1 %.5g, k2 %.5g, p1 %.5g, p2 %.5g", d[4], d[5], d[6], d[7]) + format(", k3 %.5g", d[8]) +
             (s != 1.0 ? format(", for the %.0fx%.0f image the camera wrote, scaled by %.6g", written_w, written_h, s)
                       : std::string());
    f.warning = "camera " + model_name(m) + format(": fx %.2f, fy %.2f px", f.focal_px, f.fy) +
                " and the lens distortion from drone-dji:DewarpData";
    return f;
  }
  if (m.has_dji_calibrated_focal) {
    f.focal_px = m.dji_calibrated_focal_px * s;
    f.has_center = m.has_dji_optical_center;
    f.cx = (m.dji_optical_center_x + 0.5) * s - 0.5;
    f.cy = (m.dji_optical_center_y + 0.5) * s - 0.5;
    f.source = "XMP drone-dji:CalibratedFocalLength";
    f.rule = format("calibrated focal %.2f px", m.dji_calibrated_focal_px) +
             (s != 1.0 ? format(" for the %.0fx%.0f image the camera wrote, scaled by %.6g", m.exif_width, m.exif_height, s)
                       : std::string()) +
             (f.has_center ? " and optical centre from drone-dji:CalibratedOpticalCenterX/Y" : ", image centre");
    f.warning = "camera " + model_name(m) + format(": focal %.2f px", f.focal_px) + " from the " + f.rule +
                "; no distortion: give --camera FILE for a full calibration";
    return f;
  }
  if (m.focal_35mm > 0) {
    f.source = "EXIF FocalLengthIn35mmFilm";
    double diagonal = std::hypot(width, height);
    std::string assumed;
    if (known) {
      diagonal = native_frame_diagonal_px(width, height, known->native_width, known->native_height);
      const bool crop = std::fabs(diagonal / std::hypot(width, height) - 1.0) > 1e-9;
      assumed = "native " + std::to_string(known->native_width) + "x" + std::to_string(known->native_height) +
                " frame of the camera table's " + known->name +
                (crop ? format(", of which the %.0fx%.0f photo is a crop", width, height)
                      : std::string(", the photo is the full frame"));
    } else {
      assumed = "model not in the camera table: the " + std::to_string(width) + "x" + std::to_string(height) +
                " photo taken as the sensor's full frame";
    }
    f.focal_px = m.focal_35mm / kFullFrameDiagonalMm * diagonal;
    f.rule = format("35 mm equivalent %.4g mm on the %.1f px diagonal", m.focal_35mm, diagonal) + " (" + assumed + ")";
    f.warning = "camera " + model_name(m) + format(": focal %.1f px", f.focal_px) + " from the " + f.rule +
                "; principal point at the image centre, no distortion: give --camera FILE for a calibrated camera";
    return f;
  }
  std::string message = m.path + ": no focal length in the file (no EXIF FocalLengthIn35mmFilm, no XMP "
                        "drone-dji:CalibratedFocalLength) for camera " + model_name(m) +
                        ": give --camera FILE (an OpenCV calibration) or --focal-px F (pixels at the files' size)";
  if (known) {
    const double pitch_mm = known->sensor_width_mm / known->native_width;
    const double native_long_px = std::max(known->native_width, known->native_height);
    const double scale = static_cast<double>(std::max(width, height)) / native_long_px;
    message += "; the camera table's " + known->name +
               format(" has a %.4g mm lens on a %.4g x %.4g mm sensor", known->focal_mm, known->sensor_width_mm,
                      known->sensor_height_mm) +
               " of " + std::to_string(known->native_width) + "x" + std::to_string(known->native_height) +
               format(" px: nominally --focal-px %.0f for this %.0fx%.0f photo", known->focal_mm / pitch_mm * scale,
                      width, height) +
               " (a nominal value, not a calibration; source: " + known->source + ")";
  }
  throw std::runtime_error(message);
}

}  // namespace nadir::import
