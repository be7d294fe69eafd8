#include "tools/export/photo_metadata.h"

// libexiv2 0.27's handles are std::auto_ptr, deprecated in C++17.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#include <exiv2/exiv2.hpp>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <mutex>
#include <sstream>
#include <stdexcept>

namespace nadir::exporter {
namespace {

constexpr const char* kDjiNamespace = "http://www.dji.com/drone-dji/1.0/";

void register_dji_namespace() {
  static std::once_flag once;
  std::call_once(once, [] {
    Exiv2::XmpParser::initialize();
    Exiv2::XmpProperties::registerNs(kDjiNamespace, "drone-dji");
  });
}

int64_t rounded_ms(int64_t utime) { return (utime >= 0 ? utime + 500 : utime - 500) / 1000; }

std::tm utc(int64_t seconds) {
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm parts{};
  gmtime_r(&t, &parts);
  return parts;
}

// Degrees -> EXIF "d/1 m/1 s*1e6/1e6" (unsigned; the hemisphere is the Ref tag).
std::string dms_rational(double degrees) {
  const double a = std::fabs(degrees);
  const int64_t micro_arcsec = std::llround(a * 3600.0 * 1e6);
  const int64_t d = micro_arcsec / 3600000000LL;
  const int64_t m = (micro_arcsec / 60000000LL) % 60;
  const int64_t s = micro_arcsec % 60000000LL;
  std::ostringstream text;
  text << d << "/1 " << m << "/1 " << s << "/1000000";
  return text.str();
}

// Value::toFloat is single precision: too coarse for GPS seconds.
double rational(const Exiv2::Value& v, long i) {
  const Exiv2::Rational r = v.toRational(i);
  return static_cast<double>(r.first) / r.second;
}

double dms_value(const Exiv2::Exifdatum& datum, const std::string& path) {
  const Exiv2::Value& v = datum.value();
  if (v.count() != 3) throw std::runtime_error(path + ": EXIF " + datum.key() + " is not three rationals");
  return rational(v, 0) + rational(v, 1) / 60.0 + rational(v, 2) / 3600.0;
}

std::string signed_text(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof(text), "%+.*f", decimals, value);
  return text;
}

// DJI writes its calibration as plain decimals.
std::string decimal_text(double value) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.6f", value);
  return text;
}

const Exiv2::Exifdatum& exif(const Exiv2::ExifData& data, const std::string& key, const std::string& path) {
  const auto it = data.findKey(Exiv2::ExifKey(key));
  if (it == data.end()) throw std::runtime_error(path + ": EXIF " + key + " is missing");
  return *it;
}

double xmp_number(const Exiv2::XmpData& data, const std::string& name, const std::string& path) {
  const std::string key = std::string("Xmp.drone-dji.") + name;
  const auto it = data.findKey(Exiv2::XmpKey(key));
  if (it == data.end()) throw std::runtime_error(path + ": XMP " + key + " is missing");
  const std::string text = it->toString();
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  throw std::runtime_error(path + ": XMP " + key + " = '" + text + "' is not a number");
}

}  // namespace

std::string exif_date_time(int64_t utime, int* milliseconds) {
  const int64_t ms = rounded_ms(utime);
  const int64_t seconds = ms >= 0 ? ms / 1000 : -((-ms + 999) / 1000);
  *milliseconds = static_cast<int>(ms - seconds * 1000);
  const std::tm p = utc(seconds);
  char text[80];
  std::snprintf(text, sizeof(text), "%04d:%02d:%02d %02d:%02d:%02d", p.tm_year + 1900, p.tm_mon + 1, p.tm_mday,
                p.tm_hour, p.tm_min, p.tm_sec);
  return text;
}

std::string srt_date_time(int64_t utime) {
  int ms = 0;
  std::string text = exif_date_time(utime, &ms);
  text[4] = '-';
  text[7] = '-';
  char tail[16];
  std::snprintf(tail, sizeof(tail), ".%03d", ms);
  return text + tail;
}

void write_photo_metadata(const std::string& path, const PhotoMetadata& m) {
  register_dji_namespace();
  try {
    Exiv2::Image::AutoPtr image = Exiv2::ImageFactory::open(path);
    image->readMetadata();
    Exiv2::ExifData& exif_data = image->exifData();
    int ms = 0;
    const std::string when = exif_date_time(m.utime, &ms);
    char subsec[8];
    std::snprintf(subsec, sizeof(subsec), "%03d", ms);
    exif_data["Exif.Image.Make"] = m.make;
    exif_data["Exif.Image.Model"] = m.model;
    exif_data["Exif.Image.Orientation"] = uint16_t(1);
    exif_data["Exif.Image.DateTime"] = when;
    exif_data["Exif.Photo.DateTimeOriginal"] = when;
    exif_data["Exif.Photo.DateTimeDigitized"] = when;
    exif_data["Exif.Photo.SubSecTimeOriginal"] = std::string(subsec);
    exif_data["Exif.Photo.SubSecTimeDigitized"] = std::string(subsec);
    exif_data["Exif.Photo.PixelXDimension"] = uint32_t(m.width);
    exif_data["Exif.Photo.PixelYDimension"] = uint32_t(m.height);
    exif_data["Exif.Photo.FocalLength"] = Exiv2::URational(static_cast<uint32_t>(std::llround(m.focal_length_mm * 1e4)), 10000);
    exif_data["Exif.Photo.FocalLengthIn35mmFilm"] = uint16_t(std::lround(m.focal_length_35mm));
    if (m.pixel_pitch_um > 0) {
      const Exiv2::URational per_cm(static_cast<uint32_t>(std::llround(1e4 / m.pixel_pitch_um * 1000)), 1000);
      exif_data["Exif.Photo.FocalPlaneXResolution"] = per_cm;
      exif_data["Exif.Photo.FocalPlaneYResolution"] = per_cm;
      exif_data["Exif.Photo.FocalPlaneResolutionUnit"] = uint16_t(3);  // centimetres
    }
    Exiv2::Value::AutoPtr version = Exiv2::Value::create(Exiv2::unsignedByte);
    version->read("2 3 0 0");
    exif_data.add(Exiv2::ExifKey("Exif.GPSInfo.GPSVersionID"), version.get());
    exif_data["Exif.GPSInfo.GPSLatitudeRef"] = std::string(m.latitude_deg >= 0 ? "N" : "S");
    Exiv2::Value::AutoPtr lat = Exiv2::Value::create(Exiv2::unsignedRational);
    lat->read(dms_rational(m.latitude_deg));
    exif_data.add(Exiv2::ExifKey("Exif.GPSInfo.GPSLatitude"), lat.get());
    exif_data["Exif.GPSInfo.GPSLongitudeRef"] = std::string(m.longitude_deg >= 0 ? "E" : "W");
    Exiv2::Value::AutoPtr lon = Exiv2::Value::create(Exiv2::unsignedRational);
    lon->read(dms_rational(m.longitude_deg));
    exif_data.add(Exiv2::ExifKey("Exif.GPSInfo.GPSLongitude"), lon.get());
    exif_data["Exif.GPSInfo.GPSAltitudeRef"] = uint8_t(m.altitude_m >= 0 ? 0 : 1);
    exif_data["Exif.GPSInfo.GPSAltitude"] =
        Exiv2::URational(static_cast<uint32_t>(std::llround(std::fabs(m.altitude_m) * 1000)), 1000);

    Exiv2::XmpData& xmp = image->xmpData();
    xmp["Xmp.drone-dji.GimbalRollDegree"] = signed_text(m.gimbal.roll_deg, 6);
    xmp["Xmp.drone-dji.GimbalPitchDegree"] = signed_text(m.gimbal.pitch_deg, 6);
    xmp["Xmp.drone-dji.GimbalYawDegree"] = signed_text(m.gimbal.yaw_deg, 6);
    xmp["Xmp.drone-dji.FlightRollDegree"] = signed_text(m.flight.roll_deg, 6);
    xmp["Xmp.drone-dji.FlightPitchDegree"] = signed_text(m.flight.pitch_deg, 6);
    xmp["Xmp.drone-dji.FlightYawDegree"] = signed_text(m.flight.yaw_deg, 6);
    xmp["Xmp.drone-dji.RelativeAltitude"] = signed_text(m.relative_altitude_m, 3);
    xmp["Xmp.drone-dji.AbsoluteAltitude"] = signed_text(m.absolute_altitude_m, 3);
    if (m.has_dji_calibration) {
      xmp["Xmp.drone-dji.CalibratedFocalLength"] = decimal_text(m.calibrated_focal_px);
      xmp["Xmp.drone-dji.CalibratedOpticalCenterX"] = decimal_text(m.calibrated_center_x);
      xmp["Xmp.drone-dji.CalibratedOpticalCenterY"] = decimal_text(m.calibrated_center_y);
    }
    if (!m.dewarp_data.empty()) {
      xmp["Xmp.drone-dji.DewarpData"] = m.dewarp_data;
      xmp["Xmp.drone-dji.DewarpFlag"] = "0";
    }
    image->writeMetadata();
  } catch (const Exiv2::AnyError& e) {
    throw std::runtime_error(path + ": cannot write EXIF/XMP: " + e.what());
  }
}

PhotoMetadata read_photo_metadata(const std::string& path) {
  register_dji_namespace();
  PhotoMetadata m;
  try {
    Exiv2::Image::AutoPtr image = Exiv2::ImageFactory::open(path);
    image->readMetadata();
    const Exiv2::ExifData& e = image->exifData();
    const std::string when = exif(e, "Exif.Photo.DateTimeOriginal", path).toString();
    std::tm parts{};
    if (!strptime(when.c_str(), "%Y:%m:%d %H:%M:%S", &parts)) {
      throw std::runtime_error(path + ": EXIF Exif.Photo.DateTimeOriginal = '" + when + "' is not a date and time");
    }
    const int64_t seconds = static_cast<int64_t>(timegm(&parts));
    const int ms = std::stoi(exif(e, "Exif.Photo.SubSecTimeOriginal", path).toString());
    m.utime = seconds * 1000000 + ms * 1000;
    m.make = exif(e, "Exif.Image.Make", path).toString();
    m.model = exif(e, "Exif.Image.Model", path).toString();
    m.width = static_cast<int>(exif(e, "Exif.Photo.PixelXDimension", path).toLong());
    m.height = static_cast<int>(exif(e, "Exif.Photo.PixelYDimension", path).toLong());
    m.focal_length_mm = rational(exif(e, "Exif.Photo.FocalLength", path).value(), 0);
    m.focal_length_35mm = exif(e, "Exif.Photo.FocalLengthIn35mmFilm", path).toLong();
    const auto resolution = e.findKey(Exiv2::ExifKey("Exif.Photo.FocalPlaneXResolution"));
    if (resolution != e.end()) m.pixel_pitch_um = 1e4 / rational(resolution->value(), 0);
    const double sign_lat = exif(e, "Exif.GPSInfo.GPSLatitudeRef", path).toString() == "S" ? -1 : 1;
    const double sign_lon = exif(e, "Exif.GPSInfo.GPSLongitudeRef", path).toString() == "W" ? -1 : 1;
    m.latitude_deg = sign_lat * dms_value(exif(e, "Exif.GPSInfo.GPSLatitude", path), path);
    m.longitude_deg = sign_lon * dms_value(exif(e, "Exif.GPSInfo.GPSLongitude", path), path);
    const double sign_alt = exif(e, "Exif.GPSInfo.GPSAltitudeRef", path).toLong() == 1 ? -1 : 1;
    m.altitude_m = sign_alt * rational(exif(e, "Exif.GPSInfo.GPSAltitude", path).value(), 0);
    const Exiv2::XmpData& x = image->xmpData();
    m.gimbal = {xmp_number(x, "GimbalRollDegree", path), xmp_number(x, "GimbalPitchDegree", path),
                xmp_number(x, "GimbalYawDegree", path)};
    m.flight = {xmp_number(x, "FlightRollDegree", path), xmp_number(x, "FlightPitchDegree", path),
                xmp_number(x, "FlightYawDegree", path)};
    m.relative_altitude_m = xmp_number(x, "RelativeAltitude", path);
    m.absolute_altitude_m = xmp_number(x, "AbsoluteAltitude", path);
    m.has_dji_calibration = x.findKey(Exiv2::XmpKey("Xmp.drone-dji.CalibratedFocalLength")) != x.end();
    if (m.has_dji_calibration) {
      m.calibrated_focal_px = xmp_number(x, "CalibratedFocalLength", path);
      m.calibrated_center_x = xmp_number(x, "CalibratedOpticalCenterX", path);
      m.calibrated_center_y = xmp_number(x, "CalibratedOpticalCenterY", path);
    }
    const auto dewarp = x.findKey(Exiv2::XmpKey("Xmp.drone-dji.DewarpData"));
    if (dewarp != x.end()) m.dewarp_data = dewarp->toString();
  } catch (const Exiv2::AnyError& e) {
    throw std::runtime_error(path + ": cannot read EXIF/XMP: " + e.what());
  }
  return m;
}

}  // namespace nadir::exporter
#pragma GCC diagnostic pop
