#pragma once
// Photos stored turned: a photo viewer re-saved a survey line rotated by 90,
// 180 or 270 degrees in its pixels (EXIF Orientation set or not). Found from
// the images themselves: consecutive photos are registered (ORB features, a
// similarity fitted with RANSAC), and the image rotation between them is
// compared with the one the recorded camera attitudes predict. A difference
// near a quarter turn (within `tolerance_deg`) says the later photo is stored
// turned against the earlier one. Along each chain of photos linked this way
// the orientation most photos share is the flight's (a photo whose width and
// height are swapped against most photos' cannot share it); the others are
// turned back. A photo linked to no neighbour keeps its stored orientation,
// unless its size is transposed: then which way it is turned is unknown, and
// the caller refuses it.

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace nadir::import {

struct StoredTurnOptions {
  int max_side_px = 800;         // images registered at this long side (or smaller)
  int features = 1500;           // ORB features per image
  int min_inliers = 30;          // a link needs this many RANSAC inliers ...
  double min_inlier_share = 0.1; // ... and this share of the matches
  double tolerance_deg = 20.0;   // image rotation within this of prediction + k quarter turns
  void Check() const;            // throws std::invalid_argument naming the field
};

// One photo's verdict.
struct StoredTurn {
  int quarter_turns = 0;       // the stored image is turned clockwise (on screen) by this many
                               // quarter turns against the flight's orientation: turn it back
  bool linked = false;         // registered with a neighbour (its orientation checked)
  bool size_transposed = false;  // width and height are the camera's swapped
};

// The link between a photo and the one before it.
struct StoredTurnLink {
  bool found = false;
  int inliers = 0;
  double image_rotation_deg = 0;      // measured: previous -> this photo, clockwise on screen
  double predicted_rotation_deg = 0;  // from the recorded camera attitudes
  int quarter_turns = 0;              // round((measured - predicted) / 90) mod 4
};

class StoredTurnCheck {
 public:
  explicit StoredTurnCheck(const StoredTurnOptions& options);
  // Photos in flight order. `grey`: the image as stored (empty: unreadable,
  // breaks the chain); `world_from_camera`: the recorded camera attitude
  // (x columns, y rows, z the optical axis).
  void add(const cv::Mat& grey, const Eigen::Matrix3d& world_from_camera);
  // One verdict per photo added, and the link of each to its predecessor.
  std::vector<StoredTurn> verdicts() const;
  const std::vector<StoredTurnLink>& links() const { return links_; }

 private:
  struct Features {
    std::vector<cv::Point2f> points;  // at the files' scale, centred on the image
    cv::Mat descriptors;
  };
  Features features_of(const cv::Mat& grey) const;
  StoredTurnLink link(const Features& a, const Eigen::Matrix3d& world_from_a, const Features& b,
                      const Eigen::Matrix3d& world_from_b) const;

  StoredTurnOptions options_;
  std::vector<StoredTurnLink> links_;
  std::vector<int> aspect_;  // per photo: +1 wider than high, -1 higher than wide, 0 square or unreadable
  Features previous_;
  Eigen::Matrix3d previous_attitude_ = Eigen::Matrix3d::Identity();
  bool have_previous_ = false;
};

// The image of `path` in grey, decoded at a reduced size (JPEG's 1/2, 1/4,
// 1/8 scaled decoding) with the long side at least `min_side_px`, pixels as
// stored (EXIF Orientation ignored); empty when it cannot be decoded.
cv::Mat read_grey_reduced(const std::string& path, int min_side_px, int full_width, int full_height);

// Turns `image` back by `quarter_turns` (the StoredTurn's count).
cv::Mat turn_back(const cv::Mat& image, int quarter_turns);

}  // namespace nadir::import
