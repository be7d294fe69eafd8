#pragma once
// nadir_sim log -> what a real flight brings (the round trip):
//  - a DJI-style photo survey: JPEG photos every `interval_s` of sensor time,
//    none while the aircraft turns faster than `max_yaw_rate_dps` (a survey
//    camera triggers on the lines), turned to the DJI orientation, EXIF/XMP
//    written through libexiv2, and camera.yaml (OpenCV FileStorage) for the
//    turned image;
//  - a video: MJPG AVI frames in the same orientation with a DJI-style SRT
//    and optionally a generic CSV of per-frame telemetry.
// Positions and altitudes are the simulator's truth (GPS); attitudes are the
// truth at the exposure by default, or the INS's measured attitude.

#include <cstdint>
#include <string>
#include <vector>

#include "tools/export/photo_metadata.h"
#include "tools/export/sim_log.h"

namespace nadir::exporter {

enum class AttitudeSource { kTruth, kIns };
AttitudeSource parse_attitude_source(const std::string& name);  // "truth" | "ins"; throws otherwise

struct PhotoExportOptions {
  double interval_s = 2.0;         // photo every this many seconds of sensor time
  double max_yaw_rate_dps = 3.0;   // no photo while the heading turns faster
  int quality = 95;                // JPEG quality
  double pixel_pitch_um = 5.86;    // nominal sensor pixel pitch: EXIF focal length in mm
  AttitudeSource attitude = AttitudeSource::kTruth;
  std::string model;               // EXIF Model to write (empty: "nadir_sim downward camera")
  // A 16:9 crop (full width, centre rows) of a 4:3 sensor of the photo's
  // width: EXIF gives the 35 mm equivalent of the 4:3 frame, as a camera
  // shooting 16:9 on a 4:3 sensor does.
  bool crop_16_9 = false;
  bool dji_calibration = false;    // write XMP drone-dji:CalibratedFocalLength / CalibratedOpticalCenterX/Y
  bool dji_dewarp = false;         // write XMP drone-dji:DewarpData (fx, fy, centre offset, k1 k2 p1 p2 k3), DewarpFlag 0
  // The photos of the return lines (heading more than 90 deg from the first
  // photo's) stored turned clockwise by this in their pixels, EXIF
  // Orientation 1: a photo viewer re-saved them rotated (0, 90, 180, 270).
  int return_lines_turn_deg = 0;
  // The recorded yaw (flight and gimbal) = the true one + this: a compass
  // disturbed by the site, a steady offset between the heading the photos
  // say and the images' heading.
  double yaw_offset_deg = 0.0;
  bool progress = false;
  void Check() const;              // throws std::invalid_argument naming the option and range
};

struct VideoExportOptions {
  int every = 1;                   // every Nth camera frame becomes a video frame
  AttitudeSource attitude = AttitudeSource::kTruth;
  double max_range_age_s = 0.2;    // SRT [range:] from the nearest altimeter return this close in time
  bool range = true;               // write [range:] (every frame has one, or the export fails)
  bool progress = false;
  void Check() const;
};

struct PhotoRecord {
  std::string file;                // name inside the output folder
  int64_t utime = 0;               // sensor time written into EXIF
  PhotoMetadata metadata;
  double overlap_with_previous = -1.0;  // share of the previous footprint seen again (truth, flat ground)
  double heading_change_deg = 0.0;      // truth yaw change from the previous photo
  int stored_turn_deg = 0;              // pixels stored turned clockwise by this (return_lines_turn_deg)
  double north_m = 0.0, east_m = 0.0;   // truth position in the simulator's local frame
};

struct PhotoExportResult {
  std::vector<PhotoRecord> photos;
  int64_t skipped_in_turns = 0;    // ticks with the heading rate above the limit
  int64_t ticks_without_image = 0; // ticks whose frame was dropped
  std::string camera_file;         // <dir>/camera.yaml
  CameraModel camera;              // the written photos' camera (what camera.yaml says)
  std::string attitude_source;
};

// Writes photos and camera.yaml into `out_dir` (created); throws naming the file.
PhotoExportResult export_photos(const SimLog& log, const std::string& out_dir, const PhotoExportOptions& options);

struct VideoExportResult {
  int64_t frames = 0;
  int64_t first_utime = 0, last_utime = 0;
  double fps = 0.0;
  int64_t frames_with_range = 0;
};

// Writes the AVI, the SRT and (when `csv_path` is not empty) the CSV.
VideoExportResult export_video(const SimLog& log, const std::string& video_path, const std::string& srt_path,
                               const std::string& csv_path, const VideoExportOptions& options);

// Writes the OpenCV calibration file (contract section 4) of `camera`,
// including its mount_rpy_deg.
void write_calibration(const CameraModel& camera, const std::string& path);

}  // namespace nadir::exporter
