#pragma once
// What the map readers share around GDAL: its errors kept quiet (the readers
// put the message into their own), datasets and coordinate transformations
// closed by unique_ptr, and a WGS84 point written the same way in every error.

#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cstdio>
#include <memory>
#include <string>

namespace nadir::map {

// GDAL reports through a handler that prints; while this lives it does not.
struct QuietGdal {
  QuietGdal() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;
};

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

struct CoordinateTransformDeleter {
  void operator()(OGRCoordinateTransformation* t) const { OGRCoordinateTransformation::DestroyCT(t); }
};
using Transform = std::unique_ptr<OGRCoordinateTransformation, CoordinateTransformDeleter>;

// "40.4406000, -79.9959000"
inline std::string point_text(double lat, double lon) {
  char text[64];
  std::snprintf(text, sizeof text, "%.7f, %.7f", lat, lon);
  return text;
}

}  // namespace nadir::map
