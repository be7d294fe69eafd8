#include "tools/import/camera_table.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

namespace nadir::import {
namespace {

// 1/2.3" type sensors: 6.17 x 4.55 mm is the nominal size of the type (the
// manufacturers give the type, not millimetres).
const std::vector<KnownCamera> kCameras = {
    {{"FC300S", "FC300X", "FC300C"}, "DJI Phantom 3 (Advanced / Professional / Standard)", 6.17, 4.55, 4000, 3000,
     3.61, 20,
     "DJI Phantom 3 Professional specs (dji.com/phantom-3-pro/info): 1/2.3\" CMOS, 12.4 MP, 4000x3000 (4:3), "
     "4000x2250 (16:9), FOV 94 deg, 20 mm equivalent; sensor mm: nominal 1/2.3\" type; 3.61 mm: the EXIF FocalLength "
     "these cameras write"},
    {{"FC330"}, "DJI Phantom 4", 6.17, 4.55, 4000, 3000, 3.61, 20,
     "DJI Phantom 4 specs (dji.com/phantom-4/info): 1/2.3\" CMOS, 12.4 MP, 4000x3000 (4:3), 4000x2250 (16:9), FOV 94 "
     "deg, 20 mm equivalent; sensor mm: nominal 1/2.3\" type"},
    {{"FC6310", "FC6310S"}, "DJI Phantom 4 Pro / Pro V2.0", 13.2, 8.8, 5472, 3648, 8.8, 24,
     "DJI Phantom 4 Pro V2.0 specs (dji.com/phantom-4-pro-v2/specs): 1\" CMOS, 20 MP, 5472x3648 (3:2), 4864x3648 "
     "(4:3), 5472x3078 (16:9), FOV 84 deg, 8.8 mm / 24 mm equivalent; FC6310S taken as the V2.0's Model string "
     "(not confirmed by DJI)"},
    {{"FC6310R"}, "DJI Phantom 4 RTK", 13.2, 8.8, 5472, 3648, 8.8, 24,
     "DJI Phantom 4 RTK specs (dji.com/phantom-4-rtk/info): 1\" CMOS, 20 MP, 5472x3648 (3:2), 4864x3648 (4:3), "
     "5472x3078 (16:9), FOV 84 deg, 8.8 mm / 24 mm equivalent"},
    {{"FC6360"}, "DJI P4 Multispectral", 4.8, 3.9, 1600, 1300, 5.74, 0,
     "DJI P4 Multispectral specs (dji.com/p4-multispectral/specs): six 1/2.9\" CMOS, 2.08 MP, 1600x1300, FOV 62.7 deg, "
     "5.74 mm; sensor mm approximate (DJI gives the 1/2.9\" type only); no 35 mm equivalent stated; the photos "
     "carry drone-dji:CalibratedFocalLength"},
    {{"FC7303"}, "DJI Mini 2", 6.17, 4.55, 4000, 3000, 4.49, 24,
     "DJI Mini 2 specs (dji.com/mini-2/specs): 1/2.3\" CMOS, 12 MP, 4000x3000 (4:3), 4000x2250 (16:9), FOV 83 deg, "
     "24 mm equivalent; sensor mm: nominal 1/2.3\" type; 4.49 mm: from 24 mm equivalent and the nominal type, not "
     "stated by DJI"},
    {{"M3E"}, "DJI Mavic 3 Enterprise, wide camera", 17.3, 13.0, 5280, 3956, 12.29, 24,
     "DJI Mavic 3 Enterprise specs (enterprise.dji.com/mavic-3-enterprise/specs): 4/3 CMOS, 20 MP, 5280x3956, FOV 84 "
     "deg, 24 mm equivalent; sensor mm: nominal 4/3 type; 12.29 mm: the EXIF FocalLength the camera writes"},
    {{"M3M"}, "DJI Mavic 3 Multispectral, RGB camera", 17.3, 13.0, 5280, 3956, 12.29, 24,
     "DJI Mavic 3M specs (ag.dji.com/mavic-3-m/specs): RGB 4/3 CMOS, 20 MP, 5280x3956, FOV 84 deg, 24 mm equivalent; "
     "sensor mm: nominal 4/3 type"},
    {{"M3M"}, "DJI Mavic 3 Multispectral, multispectral camera", 5.2, 3.9, 2592, 1944, 4.34, 25,
     "DJI Mavic 3M specs (ag.dji.com/mavic-3-m/specs): 1/2.8\" CMOS, 5 MP, 2592x1944, FOV 73.91 deg, 25 mm "
     "equivalent; sensor mm and 4.34 mm approximate (from the type and the 35 mm equivalent, not stated by DJI)"},
    {{"M3T"}, "DJI Mavic 3 Thermal, wide camera", 6.4, 4.8, 8000, 6000, 4.4, 24,
     "DJI Mavic 3T specs (enterprise.dji.com/mavic-3-enterprise/specs): 1/2\" CMOS, 48 MP, 8000x6000, FOV 84 deg, 24 "
     "mm equivalent; sensor mm: nominal 1/2\" type; 4.4 mm approximate"},
    {{"M3T"}, "DJI Mavic 3 Thermal, thermal camera", 7.68, 6.144, 640, 512, 9.1, 40,
     "DJI Mavic 3T specs (enterprise.dji.com/mavic-3-enterprise/specs): uncooled VOx microbolometer 640x512, 12 um "
     "pitch (sensor mm = 640 x 12 um), FOV 61 deg, 40 mm equivalent; 9.1 mm approximate"},
    {{"MAVIC2-ENTERPRISE-ADVANCED"}, "DJI Mavic 2 Enterprise Advanced, visual camera", 6.4, 4.8, 8000, 6000, 4.5, 24,
     "DJI Mavic 2 Enterprise Advanced specs (enterprise.dji.com/mavic-2-enterprise-advanced/specs): 1/2\" CMOS, 48 MP, "
     "8000x6000, 24 mm equivalent; sensor mm: nominal 1/2\" type; 4.5 mm approximate"},
    {{"MAVIC2-ENTERPRISE-ADVANCED"}, "DJI Mavic 2 Enterprise Advanced, thermal camera", 7.68, 6.144, 640, 512, 9.0,
     0,
     "DJI Mavic 2 Enterprise Advanced specs (enterprise.dji.com/mavic-2-enterprise-advanced/specs): uncooled VOx "
     "microbolometer 640x512, 12 um pitch, 9 mm lens, HFOV 40 deg; its photos carry no 35 mm equivalent"},
    {{"ZH20T"}, "DJI Zenmuse H20T, thermal camera", 7.68, 6.144, 640, 512, 13.5, 0,
     "DJI Zenmuse H20 series specs (enterprise.dji.com/zenmuse-h20-series/specs): uncooled VOx microbolometer 640x512, "
     "12 um pitch, 13.5 mm, DFOV 40.6 deg; no 35 mm equivalent stated"},
    {{"SODA"}, "senseFly S.O.D.A.", 13.2, 8.8, 5472, 3648, 10.6, 29,
     "senseFly S.O.D.A. product sheet: 1\" sensor, 20 MP, 5472x3648 (3:2), 10.6 mm, 29 mm equivalent; sensor mm: "
     "nominal 1\" type"},
    {{"Canon PowerShot ELPH 300 HS"}, "Canon PowerShot ELPH 300 HS (senseFly swinglet CAM)", 6.17, 4.55, 4000, 3000,
     4.3, 24,
     "Canon PowerShot ELPH 300 HS specifications (canon.com): 1/2.3\" CMOS, 12.1 MP, 4000x3000, 4.3-21.5 mm (24-120 "
     "mm equivalent), wide end given; sensor mm: nominal 1/2.3\" type"},
};

std::string folded(const std::string& text) {
  const size_t a = text.find_first_not_of(" \t\r\n");
  const size_t b = text.find_last_not_of(" \t\r\n");
  std::string out = a == std::string::npos ? std::string() : text.substr(a, b - a + 1);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}

}  // namespace

const std::vector<KnownCamera>& known_cameras() { return kCameras; }

const KnownCamera* find_known_camera(const std::string& model, int width, int height) {
  const std::string key = folded(model);
  if (key.empty()) return nullptr;
  const double photo_long = std::max(width, height);
  const KnownCamera* best = nullptr;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const KnownCamera& c : kCameras) {
    const bool named = std::any_of(c.models.begin(), c.models.end(), [&](const std::string& m) { return folded(m) == key; });
    if (!named) continue;
    const double distance =
        photo_long > 0 ? std::fabs(std::log(photo_long / std::max(c.native_width, c.native_height))) : 0.0;
    if (distance < best_distance) best = &c, best_distance = distance;
  }
  return best;
}

}  // namespace nadir::import
