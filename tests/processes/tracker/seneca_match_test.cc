// A real check of the descriptor matcher: consecutive photos of the shared
// Seneca flight (../shared/realdata/seneca beside the checkout: farmland,
// weak texture, crop rows, turns between photos), at half size in grey, as
// the importer publishes them. Prints the inliers per pair for each type and
// holds the default type to a share of pairs matched. Skipped when the
// folder is absent.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "processes/tracker/descriptor_matcher.h"

namespace nadir {
namespace {

const std::filesystem::path kFolder = std::filesystem::path(NADIR_SOURCE_DIR) / ".." / "shared" / "realdata" / "seneca";

struct Photo {
  std::string name;
  double heading_deg = 0;
  cv::Mat grey;  // half size
};

std::vector<Photo> load_photos() {
  std::vector<Photo> photos;
  std::ifstream csv(kFolder / "metadata.csv");
  std::string line;
  std::getline(csv, line);  // header: file,...,Heading is column 10
  while (std::getline(csv, line)) {
    std::vector<std::string> fields;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
    if (fields.size() < 11) continue;
    Photo p;
    p.name = fields[0];
    p.heading_deg = std::stod(fields[10]);
    const cv::Mat colour = cv::imread((kFolder / "images" / p.name).string(), cv::IMREAD_GRAYSCALE);
    if (colour.empty()) continue;
    cv::resize(colour, p.grey, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    photos.push_back(std::move(p));
  }
  return photos;
}

// Half of the 1200x900 photos; the focal length is the README's estimate
// (832 px at 1200 px), distortion unknown (none).
CameraModel seneca_camera() {
  CameraModel c;
  c.width = 600;
  c.height = 450;
  c.fx = c.fy = 416.0;
  c.cx = 299.5;
  c.cy = 224.5;
  c.distortion = {0, 0, 0, 0, 0};
  return c;
}

TEST(SenecaPhotos, ConsecutivePairsMatch) {
  if (!std::filesystem::exists(kFolder / "metadata.csv")) GTEST_SKIP() << "no " << kFolder;
  const std::vector<Photo> photos = load_photos();
  ASSERT_GT(photos.size(), 10u);
  const std::vector<std::string> types = {"orb", "akaze", "sift"};
  std::map<std::string, std::vector<int>> inliers;
  std::map<std::string, double> seconds;
  for (const std::string& type : types) {
    DescriptorOptions o;
    o.type = type;
    DescriptorMatcher matcher(o, seneca_camera());
    const auto start = std::chrono::steady_clock::now();
    for (const Photo& p : photos) {
      const TrackStepResult step = matcher.process(p.grey);
      inliers[type].push_back(step.first_frame ? -1 : static_cast<int>(step.tracks.size()));
    }
    seconds[type] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  std::cout << "pair                       dheading  orb akaze sift\n";
  std::map<std::string, int> matched, pairs_turning, matched_turning;
  int pairs = 0, turning = 0;
  for (size_t k = 1; k < photos.size(); ++k) {
    if (inliers["orb"][k] < 0) continue;  // size change: no pair
    ++pairs;
    double turn = std::fmod(std::abs(photos[k].heading_deg - photos[k - 1].heading_deg), 360.0);
    turn = std::min(turn, 360.0 - turn);
    const bool big_turn = turn > 90.0;
    turning += big_turn;
    std::cout << std::left << std::setw(26) << (photos[k - 1].name + "-" + photos[k].name) << std::right << std::setw(8)
              << std::fixed << std::setprecision(0) << turn;
    for (const std::string& type : types) {
      const int n = inliers[type][k];
      std::cout << std::setw(type == "orb" ? 5 : 6) << n;
      if (n >= 15) {
        ++matched[type];
        if (big_turn) ++matched_turning[type];
      }
    }
    std::cout << "\n";
  }
  for (const std::string& type : types) {
    std::vector<int> n;
    for (size_t k = 1; k < photos.size(); ++k)
      if (inliers[type][k] >= 0) n.push_back(inliers[type][k]);
    std::sort(n.begin(), n.end());
    std::cout << type << ": " << matched[type] << " of " << pairs << " pairs with >= 15 inliers (" << matched_turning[type]
              << " of " << turning << " turning > 90 deg), median " << n[n.size() / 2] << " inliers, "
              << std::setprecision(1) << 1e3 * seconds[type] / static_cast<double>(photos.size()) << " ms per photo\n";
  }
  // The default type (tracker_options.h) matches nearly every pair.
  const std::string chosen = DescriptorOptions().type;
  EXPECT_GE(matched[chosen], pairs * 9 / 10) << chosen;
}

}  // namespace
}  // namespace nadir
