#include "tools/import/photo_metadata.h"

#include <exiv2/exiv2.hpp>

#include <algorithm>
#include <cmath>
#include <locale>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "tools/import/telemetry.h"

namespace nadir::import {
namespace {

class Reader {
 public:
  Reader(const std::string& path, const Exiv2::ExifData& exif, const Exiv2::XmpData& xmp)
      : path_(path), exif_(exif), xmp_(xmp) {}

  bool exif_text(const char* key, std::string* text) const {
    const auto it = exif_.findKey(Exiv2::ExifKey(key));
    if (it == exif_.end() || it->count() == 0) return false;
    *text = trim(it->toString());
    return !text->empty();
  }
  bool exif_number(const char* key, double* v, long n = 0) const {
    const auto it = exif_.findKey(Exiv2::ExifKey(key));
    if (it == exif_.end() || it->count() <= n) return false;
    const Exiv2::Rational r = it->toRational(n);
    if (r.second == 0) throw std::runtime_error(path_ + ": " + key + " has a zero denominator");
    *v = static_cast<double>(r.first) / r.second;
    return true;
  }
  bool xmp_number(const std::string& key, double* v) const {
    const auto it = xmp_.findKey(Exiv2::XmpKey(key));
    if (it == xmp_.end()) return false;
    const std::string text = trim(it->toString());
    if (!parse_number(text, v)) throw std::runtime_error(path_ + ": " + key + " is not a number: '" + text + "'");
    return true;
  }
  bool xmp_text(const std::string& key, std::string* text) const {
    const auto it = xmp_.findKey(Exiv2::XmpKey(key));
    if (it == xmp_.end()) return false;
    *text = trim(it->toString());
    return true;
  }
  // Three XMP numbers present together (or none).
  bool xmp_triple(const std::string& prefix, const char* a, const char* b, const char* c, double* va, double* vb,
                  double* vc) const {
    const int n = xmp_number(prefix + a, va) + xmp_number(prefix + b, vb) + xmp_number(prefix + c, vc);
    if (n != 0 && n != 3) throw std::runtime_error(path_ + ": " + prefix + "{" + a + "," + b + "," + c + "} incomplete");
    return n == 3;
  }
  bool gps_coordinate(const char* key, const char* ref_key, double* deg) const {
    double d = 0, m = 0, s = 0;
    if (!exif_number(key, &d, 0)) return false;
    exif_number(key, &m, 1);
    exif_number(key, &s, 2);
    *deg = d + m / 60.0 + s / 3600.0;
    std::string ref;
    if (exif_text(ref_key, &ref) && (ref[0] == 'S' || ref[0] == 'W')) *deg = -*deg;
    return true;
  }

 private:
  const std::string& path_;
  const Exiv2::ExifData& exif_;
  const Exiv2::XmpData& xmp_;
};

}  // namespace

void register_vendor_namespaces() {
  static std::once_flag once;
  std::call_once(once, [] {
    Exiv2::XmpParser::initialize();
    for (const auto& [ns, prefix] : {std::pair<const char*, const char*>{kDjiNamespace, "drone-dji"},
                                     std::pair<const char*, const char*>{kSenseflyNamespace, "sensefly"}}) {
      try {
        Exiv2::XmpProperties::registerNs(ns, prefix);
      } catch (const Exiv2::AnyError&) {
        // already known under this prefix
      }
    }
  });
}

bool parse_dewarp_data(const std::string& text, std::array<double, 9>* values) {
  const size_t semicolon = text.find(';');
  std::string list = semicolon == std::string::npos ? text : text.substr(semicolon + 1);
  std::replace(list.begin(), list.end(), ',', ' ');
  std::istringstream in(list);
  in.imbue(std::locale::classic());
  for (double& v : *values) {
    if (!(in >> v) || !std::isfinite(v)) return false;
  }
  std::string rest;
  return !(in >> rest) && (*values)[0] > 0.0 && (*values)[1] > 0.0;
}

PhotoMetadata read_photo_metadata(const std::string& path) {
  register_vendor_namespaces();
  PhotoMetadata p;
  p.path = path;
  try {
    auto image = Exiv2::ImageFactory::open(path);
    image->readMetadata();
    const Reader r(path, image->exifData(), image->xmpData());
    std::string text;
    if (r.exif_text("Exif.Photo.DateTimeOriginal", &text)) {
      if (!parse_date_time(text, &p.time_s)) {
        throw std::runtime_error(path + ": Exif.Photo.DateTimeOriginal '" + text + "' is not YYYY:MM:DD HH:MM:SS");
      }
      p.has_time = true;
      std::string sub;
      if (r.exif_text("Exif.Photo.SubSecTimeOriginal", &sub)) {
        if (sub.find_first_not_of("0123456789") != std::string::npos) {
          throw std::runtime_error(path + ": Exif.Photo.SubSecTimeOriginal '" + sub + "' is not digits");
        }
        p.time_s += std::stod("0." + sub);
      }
    }
    p.has_gps = r.gps_coordinate("Exif.GPSInfo.GPSLatitude", "Exif.GPSInfo.GPSLatitudeRef", &p.lat_deg) &&
                r.gps_coordinate("Exif.GPSInfo.GPSLongitude", "Exif.GPSInfo.GPSLongitudeRef", &p.lon_deg);
    if (p.has_gps && r.exif_number("Exif.GPSInfo.GPSAltitude", &p.gps_alt_m)) {
      p.has_gps_alt = true;
      std::string ref;
      if (r.exif_text("Exif.GPSInfo.GPSAltitudeRef", &ref) && ref == "1") p.gps_alt_m = -p.gps_alt_m;
    }
    r.exif_number("Exif.Photo.FocalLength", &p.focal_mm);
    r.exif_number("Exif.Photo.FocalLengthIn35mmFilm", &p.focal_35mm);
    r.exif_text("Exif.Image.Make", &p.make);
    r.exif_text("Exif.Image.Model", &p.model);
    double dimension = 0;
    if (r.exif_number("Exif.Photo.PixelXDimension", &dimension)) p.exif_width = static_cast<int>(dimension);
    if (r.exif_number("Exif.Photo.PixelYDimension", &dimension)) p.exif_height = static_cast<int>(dimension);
    p.image_width = image->pixelWidth();
    p.image_height = image->pixelHeight();
    p.has_dji_calibrated_focal = r.xmp_number("Xmp.drone-dji.CalibratedFocalLength", &p.dji_calibrated_focal_px);
    if (p.has_dji_calibrated_focal && !(p.dji_calibrated_focal_px > 0)) {
      throw std::runtime_error(path + ": Xmp.drone-dji.CalibratedFocalLength is not positive");
    }
    const int centres = r.xmp_number("Xmp.drone-dji.CalibratedOpticalCenterX", &p.dji_optical_center_x) +
                        r.xmp_number("Xmp.drone-dji.CalibratedOpticalCenterY", &p.dji_optical_center_y);
    if (centres == 1) throw std::runtime_error(path + ": Xmp.drone-dji.CalibratedOpticalCenter{X,Y} incomplete");
    p.has_dji_optical_center = centres == 2;
    std::string dewarp;
    if (r.xmp_text("Xmp.drone-dji.DewarpData", &dewarp)) {
      p.has_dji_dewarp = parse_dewarp_data(dewarp, &p.dji_dewarp);
      if (!p.has_dji_dewarp) {
        throw std::runtime_error(path + ": Xmp.drone-dji.DewarpData '" + dewarp +
                                 "' is not DATE;fx,fy,cx,cy,k1,k2,p1,p2,k3 with fx, fy > 0");
      }
    }
    double flag = 0;
    if (r.xmp_number("Xmp.drone-dji.DewarpFlag", &flag)) p.dji_dewarp_flag = static_cast<int>(flag);
    p.has_dji_gimbal = r.xmp_triple("Xmp.drone-dji.", "GimbalRollDegree", "GimbalPitchDegree", "GimbalYawDegree",
                                    &p.gimbal_roll_deg, &p.gimbal_pitch_deg, &p.gimbal_yaw_deg);
    p.has_dji_flight = r.xmp_triple("Xmp.drone-dji.", "FlightRollDegree", "FlightPitchDegree", "FlightYawDegree",
                                    &p.flight_roll_deg, &p.flight_pitch_deg, &p.flight_yaw_deg);
    p.has_dji_relative_alt = r.xmp_number("Xmp.drone-dji.RelativeAltitude", &p.dji_relative_alt_m);
    p.has_dji_absolute_alt = r.xmp_number("Xmp.drone-dji.AbsoluteAltitude", &p.dji_absolute_alt_m);
    p.has_sensefly_attitude = r.xmp_triple("Xmp.sensefly.", "RollAngle", "PitchAngle", "Heading", &p.sf_roll_deg,
                                           &p.sf_pitch_deg, &p.sf_heading_deg);
    p.has_sensefly_height = r.xmp_number("Xmp.sensefly.Height", &p.sf_height_m);
    p.has_sensefly_position = r.xmp_number("Xmp.sensefly.Latitude", &p.sf_lat_deg) &&
                              r.xmp_number("Xmp.sensefly.Longitude", &p.sf_lon_deg);
    p.has_sensefly_alt = r.xmp_number("Xmp.sensefly.AltitudeAMSL", &p.sf_alt_m);
    if (r.xmp_text("Xmp.sensefly.UTCTime", &text)) {
      if (!parse_date_time(text, &p.sf_utc_s)) throw std::runtime_error(path + ": Xmp.sensefly.UTCTime '" + text + "' does not parse");
      p.has_sensefly_time = true;
    }
  } catch (const Exiv2::AnyError& e) {
    throw std::runtime_error(path + ": cannot read metadata: " + e.what());
  }
  return p;
}

}  // namespace nadir::import
