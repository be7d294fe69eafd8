#pragma once
// Writes one band of a north-up grid as a GeoTIFF with GDAL: the geotransform
// and the grid's EPSG CRS in the file, DEFLATE-compressed, no timestamps (the
// same raster gives the same bytes).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tools/map/map_grid.h"

namespace nadir::map {

// Throw std::runtime_error naming `path` when GDAL cannot create or write it.
void write_geotiff_byte(const std::string& path, const MapGrid& grid, const std::vector<uint8_t>& pixels);
void write_geotiff_float(const std::string& path, const MapGrid& grid, const std::vector<float>& pixels,
                         std::optional<double> nodata);

}  // namespace nadir::map
