#pragma once
// LCM channel names, defined once for every process, tool and test.

namespace nadir::channels {

inline constexpr const char* kCameraImage = "CAMERA_IMAGE";   // nadir.image_t
inline constexpr const char* kCameraTrigger = "CAMERA_TRIGGER"; // nadir.trigger_t
inline constexpr const char* kIns = "INS";                     // nadir.ins_t
inline constexpr const char* kAltimeter = "ALTIMETER";         // nadir.altimeter_t
inline constexpr const char* kTracks = "TRACKS";               // nadir.tracks_t
inline constexpr const char* kVoDelta = "VO_DELTA";            // nadir.vo_delta_t
inline constexpr const char* kPose = "POSE";                   // nadir.pose_t
inline constexpr const char* kGroundTruth = "GROUND_TRUTH";    // nadir.ground_truth_t
inline constexpr const char* kStatus = "STATUS";               // nadir.status_t
inline constexpr const char* kConfig = "CONFIG";               // nadir.config_t

}  // namespace nadir::channels
