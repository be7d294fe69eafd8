#pragma once
// A photo's metadata as the file holds it, read through libexiv2: EXIF time,
// GPS and focal length, and the vendor XMP of DJI (`drone-dji:`) and senseFly
// (`sensefly:`). Values are raw (vendor units and conventions); flight_import.h
// turns them into nadir's frames.

#include <array>
#include <string>
#include <vector>

namespace nadir::import {

struct PhotoMetadata {
  std::string path;
  bool has_time = false;         // Exif.Photo.DateTimeOriginal (+ SubSecTimeOriginal), camera clock as UTC
  double time_s = 0.0;
  bool has_gps = false;          // Exif.GPSInfo latitude/longitude (+ altitude)
  double lat_deg = 0, lon_deg = 0;
  bool has_gps_alt = false;
  double gps_alt_m = 0;
  double focal_mm = 0;           // Exif.Photo.FocalLength, 0 if absent
  double focal_35mm = 0;         // Exif.Photo.FocalLengthIn35mmFilm, 0 if absent
  std::string make, model;       // Exif.Image.Make / Model, empty if absent
  int exif_width = 0, exif_height = 0;    // Exif.Photo.PixelX/YDimension: the size the camera wrote, 0 if absent
  int image_width = 0, image_height = 0;  // the file's own size (its JPEG/PNG/TIFF header), 0 if unknown
  // DJI drone-dji: calibration, in pixels of the image as the camera wrote it
  bool has_dji_calibrated_focal = false;
  double dji_calibrated_focal_px = 0;    // CalibratedFocalLength
  bool has_dji_optical_center = false;
  double dji_optical_center_x = 0, dji_optical_center_y = 0;  // CalibratedOpticalCenterX/Y
  // DewarpData "DATE;fx,fy,cx,cy,k1,k2,p1,p2,k3" (cx, cy from the photo's
  // centre) and DewarpFlag (1: the image was already dewarped), as DJI
  // documents them for its enterprise cameras
  bool has_dji_dewarp = false;
  std::array<double, 9> dji_dewarp{};
  int dji_dewarp_flag = -1;  // -1: absent
  // DJI drone-dji:
  bool has_dji_gimbal = false;
  double gimbal_roll_deg = 0, gimbal_pitch_deg = 0, gimbal_yaw_deg = 0;
  bool has_dji_flight = false;
  double flight_roll_deg = 0, flight_pitch_deg = 0, flight_yaw_deg = 0;
  bool has_dji_relative_alt = false;
  double dji_relative_alt_m = 0;
  bool has_dji_absolute_alt = false;
  double dji_absolute_alt_m = 0;
  // senseFly sensefly:
  bool has_sensefly_attitude = false;
  double sf_roll_deg = 0, sf_pitch_deg = 0, sf_heading_deg = 0;
  bool has_sensefly_height = false;
  double sf_height_m = 0;
  bool has_sensefly_position = false;
  double sf_lat_deg = 0, sf_lon_deg = 0;
  bool has_sensefly_alt = false;
  double sf_alt_m = 0;             // AltitudeAMSL
  bool has_sensefly_time = false;  // UTCTime
  double sf_utc_s = 0;
};

// Reads one file's metadata; throws std::runtime_error naming the file when
// exiv2 cannot read it or a present field is malformed.
PhotoMetadata read_photo_metadata(const std::string& path);

// DJI's DewarpData text "DATE;fx,fy,cx,cy,k1,k2,p1,p2,k3" (the date part
// optional) -> the nine numbers; false unless exactly nine finite numbers
// with fx, fy > 0.
bool parse_dewarp_data(const std::string& text, std::array<double, 9>* values);

// Makes `Xmp.drone-dji.*` and `Xmp.sensefly.*` keys known to exiv2 (for
// writing; reading registers the namespaces a packet declares). Idempotent.
void register_vendor_namespaces();

inline constexpr const char* kDjiNamespace = "http://www.dji.com/drone-dji/1.0/";
inline constexpr const char* kSenseflyNamespace = "http://ns.sensefly.com/sensefly/1.0/";

}  // namespace nadir::import
