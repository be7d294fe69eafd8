#pragma once
// Files an evaluation writes: series.csv, GeoJSON and KML of both tracks.

#include <string>

#include "tools/eval/trajectory_metrics.h"

namespace nadir {

void write_series_csv(const EvalResult& result, const std::string& path);
// Both tracks as LineStrings (estimate, truth); local NED -> WGS84 by a local
// tangent-plane approximation around the reference (fine over tens of km).
void write_geojson(const EvalResult& result, const std::string& path);
void write_kml(const EvalResult& result, const std::string& path);

}  // namespace nadir
