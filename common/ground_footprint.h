#pragma once
// What a photo sees of the ground: the camera's footprint cast from a body
// pose onto a level plane, and how much two footprints share. A photo export
// uses it to space its photos, an evaluation to tell the frame pairs that no
// tracker could have matched (footprints apart) from the rest.

#include <Eigen/Core>
#include <vector>

#include "common/camera_model.h"

namespace nadir {

// The image boundary (corners and edge midpoints, for distortion) cast from a
// body at `position_ned` with attitude `world_from_body` onto the level plane
// at NED down coordinate `ground_down_m`, as (north, east) points in boundary
// order. Boundary points at or above the horizon have no footprint and are
// left out.
std::vector<Eigen::Vector2d> ground_footprint(const CameraModel& camera, const Eigen::Vector3d& position_ned,
                                              const Eigen::Matrix3d& world_from_body, double ground_down_m);

// Share of footprint A's area (the convex hull of its points) inside footprint
// B's, 0..1; 0 when either has fewer than three points.
double footprint_overlap(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b);

}  // namespace nadir
