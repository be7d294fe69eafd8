#pragma once
// nadir's LCM channels as Foxglove topics: which topics each channel feeds,
// their schemas, and each message as JSON. Shared by the live bridge
// (nadir_foxglove) and the MCAP export (nadir_log export --mcap), so a
// recorded flight opens in Foxglove exactly like a live one.
//
// World frame "map": east-north-up about POSE's origin (Foxglove's 3-D panel
// is z-up); bodies "base_link" (estimate) and "truth_base_link" (simulator
// truth) are forward-left-up, "base_link_level" the estimate's level frame
// (heading only), which VO_GROUND's points are in. The truth's NED origin is
// the simulator's (on the ground below the start): its map views start at the
// first POSE, relative to the truth there, as nadir_eval aligns them.

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "common/geodetic.h"
#include "common/pose_origin.h"

namespace nadir {

struct FoxgloveTopic {
  std::string name;         // e.g. "POSE/fix"
  std::string lcm_channel;  // e.g. "POSE"
  std::string schema_name;  // e.g. "foxglove.LocationFix"
};

struct FoxgloveMessage {
  int topic = 0;            // index into FoxgloveTranslator::topics()
  int64_t time_ns = 0;      // the message's sensor time (utime) in ns
  std::string json;
};

struct FoxgloveTranslatorOptions {
  // POSE's NED origin on the globe: the INS position at the first POSE's
  // sensor time (common/pose_origin.h; the NED origin is the position at the
  // first frame), or `origin` when origin_from_ins is false. Until the INS
  // gives it, no LocationFix.
  bool origin_from_ins = true;
  GeodeticPoint origin;
  double image_rate_hz = 0.0;  // CAMERA_IMAGE at most this often (sensor time); 0: every frame
};

class FoxgloveTranslator {
 public:
  explicit FoxgloveTranslator(const FoxgloveTranslatorOptions& options);

  const std::vector<FoxgloveTopic>& topics() const { return topics_; }
  // The LCM channels that feed at least one topic, in topics() order.
  std::vector<std::string> lcm_channels() const;

  // The messages one LCM message gives, for the topics `wanted` accepts (all
  // when empty): nothing is encoded for a topic nobody wants. Returns false
  // with `reason` when the message does not decode as its channel's type;
  // true with no message for a channel without topics or a decimated image.
  bool translate(const std::string& channel, const uint8_t* data, size_t size,
                 const std::function<bool(int topic)>& wanted, std::vector<FoxgloveMessage>* out,
                 std::string* reason);

  int64_t images_decimated() const { return images_decimated_; }

 private:
  FoxgloveTranslatorOptions options_;
  // The estimate's and the truth's paths on the globe from the origin.
  GeodeticTrack pose_track_, truth_track_;
  bool origin_known_ = false;
  PoseOrigin pose_origin_;
  // The truth's recent positions until the first POSE (interpolated at its
  // time: truth and POSE need not arrive in time order), then the truth's NED
  // less POSE's there.
  struct TruthSample {
    int64_t utime;
    Eigen::Vector3d ned;
  };
  std::deque<TruthSample> recent_truth_;
  bool truth_origin_known_ = false;
  Eigen::Vector3d truth_offset_ned_ = Eigen::Vector3d::Zero();
  std::vector<FoxgloveTopic> topics_;
  int64_t last_image_bucket_ = -1;
  int64_t images_decimated_ = 0;
};

}  // namespace nadir
