#pragma once
// JSON schemas of the Foxglove topics nadir serves and exports: the subset of
// Foxglove's well-known schemas (foxglove.LocationFix, PoseInFrame,
// FrameTransform, RawImage, ImageAnnotations) that nadir fills, and nadir's
// own plain-JSON views of its LCM types (nadir.Pose, nadir.VoDelta, ...).
// The tests validate every message against Foxglove's published schemas.

#include <string>

namespace nadir::foxglove_schemas {

// The schema (JSON Schema text) for a schema name such as
// "foxglove.LocationFix" or "nadir.VoDelta"; throws std::invalid_argument
// naming an unknown one.
std::string schema_text(const std::string& schema_name);

}  // namespace nadir::foxglove_schemas
