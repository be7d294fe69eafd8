// Photos stored turned by a quarter turn or two are found from the images and
// the recorded attitudes, and turned back exactly; a photo the images cannot
// link keeps its stored orientation. Views of one textured ground along a
// line, the camera's heading drifting as a real survey's does.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

#include "common/geometry.h"
#include "tools/import/stored_turn.h"

namespace nadir::import {
namespace {

constexpr int kWidth = 800, kHeight = 600;

// Blobs of several sizes: corners at every scale ORB looks at.
cv::Mat ground() {
  cv::RNG rng(7);
  cv::Mat coarse(300, 300, CV_8U), fine(3000, 3000, CV_8U), texture;
  rng.fill(coarse, cv::RNG::UNIFORM, 0, 256);
  rng.fill(fine, cv::RNG::UNIFORM, 0, 256);
  cv::resize(coarse, texture, fine.size(), 0, 0, cv::INTER_CUBIC);
  cv::GaussianBlur(fine, fine, cv::Size(0, 0), 2.0);
  cv::addWeighted(texture, 0.7, fine, 0.6, -40.0, texture);
  return texture;
}

// The camera over ground point `centre`, its columns along heading `yaw`
// (radians, clockwise on the texture): pixel p (centred) sees centre + R(yaw) p.
cv::Mat view(const cv::Mat& texture, cv::Point2d centre, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double cx = 0.5 * (kWidth - 1), cy = 0.5 * (kHeight - 1);
  cv::Mat map = (cv::Mat_<double>(2, 3) << c, -s, centre.x - c * cx + s * cy, s, c, centre.y - s * cx - c * cy);
  cv::Mat out;
  cv::warpAffine(texture, out, map, cv::Size(kWidth, kHeight), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP);
  return out;
}

Eigen::Matrix3d attitude(double yaw) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  r(0, 0) = std::cos(yaw), r(0, 1) = -std::sin(yaw), r(1, 0) = std::sin(yaw), r(1, 1) = std::cos(yaw);
  return r;
}

struct Survey {
  std::vector<cv::Mat> views;
  std::vector<double> yaws;
};

// `n` views 110 px apart along the texture's columns (86 % overlap), the heading wandering by a few degrees.
Survey line_survey(int n) {
  const cv::Mat texture = ground();
  Survey s;
  for (int i = 0; i < n; ++i) {
    const double yaw = deg_to_rad(3.0 * std::sin(0.7 * i) + 0.8 * i);
    s.views.push_back(view(texture, cv::Point2d(900.0 + 110.0 * i, 1500.0), yaw));
    s.yaws.push_back(yaw);
  }
  return s;
}

std::vector<cv::Mat> deep_copy(const std::vector<cv::Mat>& images) {
  std::vector<cv::Mat> out;
  for (const cv::Mat& m : images) out.push_back(m.clone());
  return out;
}

std::vector<StoredTurn> check(const Survey& s) {
  StoredTurnCheck check{StoredTurnOptions{}};
  for (size_t i = 0; i < s.views.size(); ++i) check.add(s.views[i], attitude(s.yaws[i]));
  for (size_t i = 1; i < s.views.size(); ++i) {
    const StoredTurnLink& l = check.links()[i];
    if (l.found) {
      // The measured rotation is the predicted one plus the stored turn, to a fraction of a degree.
      EXPECT_NEAR(std::remainder(l.image_rotation_deg - l.predicted_rotation_deg - 90.0 * l.quarter_turns, 360.0), 0.0,
                  0.5)
          << "photo " << i;
    }
  }
  return check.verdicts();
}

TEST(StoredTurn, PhotosAsRecordedAreLeftAlone) {
  const Survey s = line_survey(8);
  const std::vector<StoredTurn> v = check(s);
  ASSERT_EQ(v.size(), 8u);
  for (size_t i = 0; i < v.size(); ++i) {
    EXPECT_TRUE(v[i].linked) << i;
    EXPECT_EQ(v[i].quarter_turns, 0) << i;
  }
}

TEST(StoredTurn, ALineStoredHalfTurnedIsFoundAndTurnedBackExactly) {
  Survey s = line_survey(9);
  const std::vector<cv::Mat> original = deep_copy(s.views);
  for (size_t i = 5; i < s.views.size(); ++i) cv::rotate(original[i], s.views[i], cv::ROTATE_180);
  const std::vector<StoredTurn> v = check(s);
  for (size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(v[i].quarter_turns, i < 5 ? 0 : 2) << i;
    EXPECT_EQ(cv::norm(turn_back(s.views[i], v[i].quarter_turns), original[i], cv::NORM_INF), 0.0) << i;
  }
}

TEST(StoredTurn, TheMajorityIsTheFlightsOrientationEvenWhenTheFirstPhotosAreTurned) {
  Survey s = line_survey(8);
  for (size_t i = 0; i < 3; ++i) cv::rotate(s.views[i], s.views[i], cv::ROTATE_180);
  const std::vector<StoredTurn> v = check(s);
  for (size_t i = 0; i < v.size(); ++i) EXPECT_EQ(v[i].quarter_turns, i < 3 ? 2 : 0) << i;
}

TEST(StoredTurn, QuarterTurnsBothWaysWithTheSizeTransposed) {
  Survey s = line_survey(7);
  const std::vector<cv::Mat> original = deep_copy(s.views);
  cv::rotate(original[2], s.views[2], cv::ROTATE_90_CLOCKWISE);
  cv::rotate(original[5], s.views[5], cv::ROTATE_90_COUNTERCLOCKWISE);
  const std::vector<StoredTurn> v = check(s);
  const std::vector<int> expected{0, 0, 1, 0, 0, 3, 0};
  for (size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(v[i].quarter_turns, expected[i]) << i;
    EXPECT_EQ(v[i].size_transposed, expected[i] % 2 == 1) << i;
    EXPECT_EQ(cv::norm(turn_back(s.views[i], v[i].quarter_turns), original[i], cv::NORM_INF), 0.0) << i;
  }
}

TEST(StoredTurn, APhotoNoNeighbourMatchesIsNotLinkedAndKeepsItsOrientation) {
  Survey s = line_survey(6);
  s.views[3] = cv::Mat(kHeight, kWidth, CV_8U, cv::Scalar(128));  // featureless: no link either side
  cv::rotate(s.views[5], s.views[5], cv::ROTATE_180);              // the chain after it: one photo, unchecked
  const std::vector<StoredTurn> v = check(s);
  for (size_t i = 0; i < 3; ++i) EXPECT_TRUE(v[i].linked) << i;
  EXPECT_FALSE(v[3].linked);
  EXPECT_EQ(v[3].quarter_turns, 0);
  // Photos 4 and 5 link to each other (a chain of two): one of them is turned against the other,
  // and with no majority the earlier one's orientation is taken.
  EXPECT_TRUE(v[4].linked);
  EXPECT_EQ(v[4].quarter_turns, 0);
  EXPECT_EQ(v[5].quarter_turns, 2);
}

TEST(StoredTurn, OptionsOutOfRangeAreRefusedNamingTheField) {
  StoredTurnOptions o;
  o.tolerance_deg = 60.0;
  try {
    StoredTurnCheck check(o);
    FAIL() << "accepted tolerance_deg 60";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tolerance_deg"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nadir::import
