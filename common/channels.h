#pragma once
// LCM channel names, defined once for every process, tool and test.

#include <string>

namespace nadir::channels {

inline constexpr const char* kCameraImage = "CAMERA_IMAGE";   // nadir.image_t
inline constexpr const char* kCameraTrigger = "CAMERA_TRIGGER"; // nadir.trigger_t
inline constexpr const char* kIns = "INS";                     // nadir.ins_t
inline constexpr const char* kAltimeter = "ALTIMETER";         // nadir.altimeter_t
inline constexpr const char* kTracks = "TRACKS";               // nadir.tracks_t
inline constexpr const char* kVoDelta = "VO_DELTA";            // nadir.vo_delta_t
inline constexpr const char* kVoGround = "VO_GROUND";          // nadir.ground_points_t
inline constexpr const char* kPose = "POSE";                   // nadir.pose_t
inline constexpr const char* kMapFix = "MAP_FIX";              // nadir.map_fix_t
inline constexpr const char* kGroundTruth = "GROUND_TRUTH";    // nadir.ground_truth_t
inline constexpr const char* kStatus = "STATUS";               // nadir.status_t
inline constexpr const char* kConfig = "CONFIG";               // nadir.config_t
// LCM's own: every udpm instance sends one to itself at start. It belongs to
// the bus it was sent on and is never relayed onto another.
inline constexpr const char* kLcmSelfTest = "LCM_SELF_TEST";

// STATUS and CONFIG: a process's bookkeeping, stamped when sent. Neither has
// a sensor-time latency nor counts as traffic of the pipeline.
inline bool is_bookkeeping(const std::string& channel) { return channel == kStatus || channel == kConfig; }

}  // namespace nadir::channels
