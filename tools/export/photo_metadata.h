#pragma once
// A survey photo's metadata as a DJI drone writes it, through libexiv2:
// EXIF time (DateTimeOriginal + SubSecTimeOriginal in ms), camera, focal
// length, GPS; XMP drone-dji: gimbal and flight attitude, relative and
// absolute altitude. Reading it back is for tests and checks.

#include <cstdint>
#include <string>

#include "tools/export/dji_orientation.h"

namespace nadir::exporter {

struct PhotoMetadata {
  int64_t utime = 0;  // UTC microseconds; written to the millisecond
  std::string make = "nadir";
  std::string model = "nadir_sim downward camera";
  int width = 0, height = 0;
  double focal_length_mm = 0.0;
  double focal_length_35mm = 0.0;  // 35 mm equivalent (diagonal of the sensor's full frame), rounded on write
  bool has_dji_calibration = false;  // XMP drone-dji:CalibratedFocalLength / CalibratedOpticalCenterX/Y
  double calibrated_focal_px = 0.0, calibrated_center_x = 0.0, calibrated_center_y = 0.0;
  std::string dewarp_data;         // XMP drone-dji:DewarpData "DATE;fx,fy,cx,cy,k1,k2,p1,p2,k3" (+ DewarpFlag 0); empty: none
  double pixel_pitch_um = 0.0;     // -> FocalPlaneX/YResolution (pixels per cm)
  double latitude_deg = 0.0, longitude_deg = 0.0, altitude_m = 0.0;  // GPS; altitude ellipsoidal
  DjiAngles gimbal;                // camera attitude (contract section 3)
  DjiAngles flight;                // body attitude, ZYX as nadir's
  double relative_altitude_m = 0.0;  // above the take-off point
  double absolute_altitude_m = 0.0;
};

// "YYYY:MM:DD HH:MM:SS" (EXIF) and the milliseconds of `utime` (rounded).
std::string exif_date_time(int64_t utime, int* milliseconds);
// "YYYY-MM-DD HH:MM:SS.mmm" (DJI SRT).
std::string srt_date_time(int64_t utime);

// Writes the metadata into the existing JPEG `path`; throws naming the file.
void write_photo_metadata(const std::string& path, const PhotoMetadata& metadata);
// Reads it back; throws naming the file and the missing or malformed key.
PhotoMetadata read_photo_metadata(const std::string& path);

}  // namespace nadir::exporter
