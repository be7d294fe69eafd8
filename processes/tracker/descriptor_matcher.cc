#include "processes/tracker/descriptor_matcher.h"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace nadir {

namespace {

const DescriptorOptions& checked(const DescriptorOptions& options) {
  options.Check("tracker descriptor options");
  return options;
}

// Detectors tuned for weak texture and with more keypoints than kept, so the
// grid selection has something to choose from in every cell.
cv::Ptr<cv::Feature2D> make_detector(const DescriptorOptions& o) {
  const int detect = 3 * o.max_features;
  if (o.type == "akaze") {
    return cv::AKAZE::create(cv::AKAZE::DESCRIPTOR_MLDB, 0, 3, static_cast<float>(o.akaze_threshold), 4, 4,
                             cv::KAZE::DIFF_PM_G2);
  }
  if (o.type == "sift") return cv::SIFT::create(detect, 3, o.sift_contrast_threshold, 10.0, 1.6);
  return cv::ORB::create(detect, 1.2f, o.orb_levels, 31, 0, 2, cv::ORB::HARRIS_SCORE, 31, o.orb_fast_threshold);
}

}  // namespace

DescriptorMatcher::DescriptorMatcher(const DescriptorOptions& options, const CameraModel& camera)
    : options_(checked(options)),
      camera_(camera),
      detector_(make_detector(options)),
      norm_type_(options.type == "sift" ? cv::NORM_L2 : cv::NORM_HAMMING) {}

void DescriptorMatcher::reset() {
  have_reference_ = false;
  reference_ = DescribedFrame();
}

DescribedFrame DescriptorMatcher::describe(const cv::Mat& image) const {
  if (image.empty() || image.type() != CV_8UC1) {
    throw std::invalid_argument("DescriptorMatcher needs a non-empty 8-bit single-channel image");
  }
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  detector_->detectAndCompute(image, cv::noArray(), keypoints, descriptors);

  // A total order that does not depend on how the detector produced them.
  std::vector<int> order(keypoints.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const cv::KeyPoint& p = keypoints[static_cast<size_t>(a)];
    const cv::KeyPoint& q = keypoints[static_cast<size_t>(b)];
    return std::make_tuple(-p.response, p.pt.y, p.pt.x, p.size, p.angle, p.octave, a) <
           std::make_tuple(-q.response, q.pt.y, q.pt.x, q.size, q.angle, q.octave, b);
  });

  // Spread: each grid cell first keeps its strongest max_features / cells,
  // then the strongest of the rest fill the budget.
  const int cells = options_.grid_cols * options_.grid_rows;
  const int quota = std::max(1, options_.max_features / cells);
  const float b = static_cast<float>(options_.border_px);
  const auto inside = [&](const cv::Point2f& p) {
    return p.x >= b && p.y >= b && p.x <= static_cast<float>(image.cols - 1) - b &&
           p.y <= static_cast<float>(image.rows - 1) - b;
  };
  const auto cell_of = [&](const cv::Point2f& p) {
    const int cx = std::clamp(static_cast<int>(p.x * static_cast<float>(options_.grid_cols) / static_cast<float>(image.cols)), 0,
                              options_.grid_cols - 1);
    const int cy = std::clamp(static_cast<int>(p.y * static_cast<float>(options_.grid_rows) / static_cast<float>(image.rows)), 0,
                              options_.grid_rows - 1);
    return cy * options_.grid_cols + cx;
  };
  std::vector<int> per_cell(static_cast<size_t>(cells), 0);
  std::vector<char> taken(keypoints.size(), 0);
  int kept = 0;
  for (int i : order) {
    const cv::Point2f& p = keypoints[static_cast<size_t>(i)].pt;
    if (kept >= options_.max_features || !inside(p)) continue;
    int& in_cell = per_cell[static_cast<size_t>(cell_of(p))];
    if (in_cell >= quota) continue;
    ++in_cell;
    ++kept;
    taken[static_cast<size_t>(i)] = 1;
  }
  for (int i : order) {
    if (kept >= options_.max_features) break;
    if (taken[static_cast<size_t>(i)] || !inside(keypoints[static_cast<size_t>(i)].pt)) continue;
    taken[static_cast<size_t>(i)] = 1;
    ++kept;
  }

  DescribedFrame frame;
  frame.descriptors.create(kept, descriptors.cols, descriptors.type());
  int row = 0;
  for (int i : order) {
    if (!taken[static_cast<size_t>(i)]) continue;
    frame.px.push_back(keypoints[static_cast<size_t>(i)].pt);
    descriptors.row(i).copyTo(frame.descriptors.row(row++));
  }
  frame.norm = camera_.undistort(frame.px);
  frame.ids.assign(frame.px.size(), 0);
  frame.ages.assign(frame.px.size(), 1);
  return frame;
}

std::vector<DescriptorMatch> DescriptorMatcher::candidates(const DescribedFrame& prev, const DescribedFrame& curr) const {
  std::vector<DescriptorMatch> out;
  const int nc = curr.descriptors.rows, np = prev.descriptors.rows;
  if (np < 2 || nc < 2) return out;
  // All distances once (rows: current keypoints, columns: reference ones);
  // the ratio test reads each row's two smallest, the cross check each
  // column's smallest. The first index wins a tie, as in cv::BFMatcher.
  cv::Mat distance;
  cv::batchDistance(curr.descriptors, prev.descriptors, distance, norm_type_ == cv::NORM_HAMMING ? CV_32S : CV_32F,
                    cv::noArray(), norm_type_);
  if (distance.type() != CV_32F) distance.convertTo(distance, CV_32F);
  std::vector<int> best(static_cast<size_t>(nc), -1);
  std::vector<float> best_d(static_cast<size_t>(nc)), second_d(static_cast<size_t>(nc));
  std::vector<int> column_best(static_cast<size_t>(np), -1);
  std::vector<float> column_d(static_cast<size_t>(np), 0.0f);
  for (int q = 0; q < nc; ++q) {
    const float* row = distance.ptr<float>(q);
    float d1 = std::numeric_limits<float>::max(), d2 = d1;
    int b1 = -1;
    for (int p = 0; p < np; ++p) {
      const float d = row[p];
      if (d < d1) {
        d2 = d1;
        d1 = d;
        b1 = p;
      } else if (d < d2) {
        d2 = d;
      }
      const size_t c = static_cast<size_t>(p);
      if (column_best[c] < 0 || d < column_d[c]) {
        column_best[c] = q;
        column_d[c] = d;
      }
    }
    best[static_cast<size_t>(q)] = b1;
    best_d[static_cast<size_t>(q)] = d1;
    second_d[static_cast<size_t>(q)] = d2;
  }
  // Each reference keypoint goes to one current keypoint at most (its ids
  // must stay unique): the closest, the first on a tie.
  std::vector<int> owner(static_cast<size_t>(np), -1);
  std::vector<float> owner_distance(owner.size(), 0.0f);
  for (int q = 0; q < nc; ++q) {
    const size_t i = static_cast<size_t>(q);
    if (options_.ratio < 1.0 && !(best_d[i] < static_cast<float>(options_.ratio) * second_d[i])) continue;
    const size_t p = static_cast<size_t>(best[i]);
    if (options_.cross_check && column_best[p] != q) continue;
    if (owner[p] >= 0 && owner_distance[p] <= best_d[i]) continue;
    owner[p] = q;
    owner_distance[p] = best_d[i];
  }
  for (size_t p = 0; p < owner.size(); ++p)
    if (owner[p] >= 0) out.push_back({static_cast<int>(p), owner[p]});
  std::sort(out.begin(), out.end(), [](const DescriptorMatch& a, const DescriptorMatch& b) { return a.curr < b.curr; });
  return out;
}

std::vector<DescriptorMatch> DescriptorMatcher::geometric_inliers(const std::vector<cv::Point2d>& prev_norm,
                                                                  const std::vector<cv::Point2d>& curr_norm,
                                                                  const std::vector<DescriptorMatch>& matches) const {
  std::vector<DescriptorMatch> out;
  if (static_cast<int>(matches.size()) < options_.min_matches) return out;
  std::vector<cv::Point2f> a, b;
  a.reserve(matches.size());
  b.reserve(matches.size());
  for (const DescriptorMatch& m : matches) {
    const cv::Point2d& p = prev_norm[static_cast<size_t>(m.prev)];
    const cv::Point2d& c = curr_norm[static_cast<size_t>(m.curr)];
    a.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
    b.emplace_back(static_cast<float>(c.x), static_cast<float>(c.y));
  }
  // The threshold in normalized units: pixels at the focal length.
  const double threshold = options_.ransac_threshold_px / camera_.fx;
  cv::Mat mask, model;
  if (options_.geometry == "fundamental") {
    model = cv::findFundamentalMat(a, b, cv::FM_RANSAC, threshold, options_.ransac_confidence,
                                   options_.ransac_max_iterations, mask);
  } else {
    model = cv::findHomography(a, b, cv::RANSAC, threshold, mask, options_.ransac_max_iterations,
                               options_.ransac_confidence);
  }
  if (model.empty() || mask.empty()) return out;
  for (size_t i = 0; i < matches.size(); ++i)
    if (mask.at<uchar>(static_cast<int>(i)) != 0) out.push_back(matches[i]);
  if (static_cast<int>(out.size()) < options_.min_matches) out.clear();
  return out;
}

void DescriptorMatcher::set_reference(const cv::Mat& image) {
  reference_ = describe(image);
  for (int64_t& id : reference_.ids) id = next_id_++;
  image_size_ = image.size();
  have_reference_ = true;
}

TrackStepResult DescriptorMatcher::process(const cv::Mat& image) {
  if (have_reference_ && image.size() != image_size_) reset();
  TrackStepResult result;
  stats_ = DescriptorStepStats();
  DescribedFrame curr = describe(image);
  stats_.keypoints = static_cast<int>(curr.px.size());
  if (!have_reference_) {
    result.first_frame = true;
  } else {
    const std::vector<DescriptorMatch> cands = candidates(reference_, curr);
    const std::vector<DescriptorMatch> inliers = geometric_inliers(reference_.norm, curr.norm, cands);
    stats_.candidates = static_cast<int>(cands.size());
    stats_.inliers = static_cast<int>(inliers.size());
    stats_.geometry_failed = inliers.empty();
    result.attempted = static_cast<int>(reference_.px.size());
    for (const DescriptorMatch& m : inliers) {
      const size_t p = static_cast<size_t>(m.prev), c = static_cast<size_t>(m.curr);
      curr.ids[c] = reference_.ids[p];
      curr.ages[c] = reference_.ages[p] + 1;
      result.tracks.push_back({curr.ids[c], curr.ages[c], reference_.px[p], curr.px[c]});
    }
    std::sort(result.tracks.begin(), result.tracks.end(),
              [](const FeatureTrack& x, const FeatureTrack& y) { return x.id < y.id; });
  }
  for (int64_t& id : curr.ids)
    if (id == 0) id = next_id_++;
  reference_ = std::move(curr);
  image_size_ = image.size();
  have_reference_ = true;
  result.features_after = stats_.keypoints;
  result.replenished = stats_.keypoints - stats_.inliers;
  return result;
}

}  // namespace nadir
