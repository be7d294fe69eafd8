#pragma once
// Where a north-up template of the ground (an orthorectified frame) lies in a
// larger north-up window of the map around the same point: normalised
// cross-correlation over every shift within the search radius, the peak to a
// fraction of a pixel, and the figures that say whether to trust it.
//
//   score       the correlation at the peak (-1..1);
//   peak_ratio  the peak over its best rival: the highest local maximum of
//               the surface farther from it than its half-peak radius (or,
//               without one, the highest point that far): near 1 on
//               repetitive ground, where another shift fits almost as well,
//               however high the surface stays between the two;
//   at_edge     the peak on the border of the search: the true shift may lie
//               beyond it;
//   hessian     curvature of the correlation surface at the peak (per px^2),
//               whose inverse gives the shape of the fix's covariance.

#include <opencv2/core.hpp>

#include <Eigen/Core>

namespace nadir {

struct Registration {
  bool found = false;           // false: a window smaller than the template, or a flat surface
  Eigen::Vector2d shift_px = Eigen::Vector2d::Zero();  // (east, south) = (column, row) shift of the template
  double score = -1.0;
  double second_score = -1.0;   // best outside the peak's lobe (-1: none)
  double peak_ratio = 0.0;
  bool at_edge = false;
  Eigen::Matrix2d hessian = Eigen::Matrix2d::Zero();  // d2 score / d(col, row)^2 at the peak
  int lobe_pixels = 0;  // pixels within the half-peak radius
  cv::Point peak_px;    // the peak's whole-pixel place on the surface: the template's top-left corner in the window
};

// `window` (CV_32F, size w x w) holds the template's ground when shifted by
// at most (w - t) / 2 pixels; `templ` (CV_32F, t x t, t <= w). The shift is
// of the template's centre from the window's centre.
Registration register_template(const cv::Mat& window, const cv::Mat& templ);

// How well the window's own ground at the peak (the template-sized square
// with its top-left corner at `at`) fits elsewhere in the window: the best
// rival of its correlation with the whole window, chosen as for the peak's
// rival. Near 1 where the map repeats itself within the search (fields in
// rows, a copy of the same ground): one period fits the frame as well as
// another whatever the frame's own correlation says. -1 when the square does
// not fit in the window.
double map_self_similarity(const cv::Mat& window, cv::Point at, int size);

// What is matched: the gradient magnitude of the grey values smoothed by a
// Gaussian of `blur_px`. A map flown in another season keeps the ground's
// edges (field boundaries, roads, tree lines) where its grey levels change
// class by class, and a slope lit from the other side keeps its edges too:
// on simulated maps the raw grey values of frame and map correlated at 0.04
// where their gradient magnitudes did at 0.42 (docs/maps.md).
cv::Mat edge_strength(const cv::Mat& grey, double blur_px = 0.8);

// Mean of an edge picture: the ground's edge strength in grey levels per
// pixel. Smooth shading of relief and a weak texture under the camera's
// noise give a fraction of what field boundaries, roads and hedges give.
double mean_edge_strength(const cv::Mat& edges);

// Standard deviation of the grey values where `valid` is set (all if empty).
double texture_stddev(const cv::Mat& grey, const cv::Mat& valid = cv::Mat());

}  // namespace nadir
