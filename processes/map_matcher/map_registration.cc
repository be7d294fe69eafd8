#include "processes/map_matcher/map_registration.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace nadir {

namespace {

// The peak's radius: the farthest, along the four axis directions, that the
// surface stays above half the peak.
int half_peak_radius(const cv::Mat& surface, cv::Point peak) {
  const float half = 0.5f * surface.at<float>(peak);
  int radius = 1;
  const cv::Point steps[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (const cv::Point& step : steps) {
    int r = 1;
    for (cv::Point q = peak + step; q.x >= 0 && q.y >= 0 && q.x < surface.cols && q.y < surface.rows; q += step, ++r) {
      if (surface.at<float>(q) <= half) break;
    }
    radius = std::max(radius, r);
  }
  return radius;
}

// The best rival of the peak: the highest local maximum (3 x 3) farther than
// `radius` from it -- on repetitive ground the next period's peak, however
// high the surface stays between them -- or, without one, the highest point
// that far (the flank of a single peak). -1 when nothing is that far.
double best_rival(const cv::Mat& surface, cv::Point peak, int radius, int* pixels_within) {
  cv::Mat dilated;
  cv::dilate(surface, dilated, cv::Mat::ones(3, 3, CV_8U));
  double rival_max = -1.0, flank_max = -1.0;
  int within = 0;
  for (int y = 0; y < surface.rows; ++y) {
    const float* s = surface.ptr<float>(y);
    const float* d = dilated.ptr<float>(y);
    for (int x = 0; x < surface.cols; ++x) {
      const int dx = x - peak.x, dy = y - peak.y;
      if (dx * dx + dy * dy <= radius * radius) {
        ++within;
        continue;
      }
      flank_max = std::max(flank_max, static_cast<double>(s[x]));
      if (s[x] >= d[x]) rival_max = std::max(rival_max, static_cast<double>(s[x]));
    }
  }
  *pixels_within = within;
  return rival_max > -1.0 ? rival_max : flank_max;
}

// Vertex offset of a parabola through (-1, a), (0, b), (1, c), within +-0.5.
double parabola_vertex(double a, double b, double c) {
  const double denominator = a - 2.0 * b + c;
  if (!(denominator < 0.0)) return 0.0;
  return std::clamp(0.5 * (a - c) / denominator, -0.5, 0.5);
}

}  // namespace

cv::Mat edge_strength(const cv::Mat& grey, double blur_px) {
  cv::Mat smooth, gx, gy, magnitude;
  cv::GaussianBlur(grey, smooth, cv::Size(), blur_px, blur_px, cv::BORDER_REFLECT);
  cv::Sobel(smooth, gx, CV_32F, 1, 0, 3, 0.125, 0.0, cv::BORDER_REFLECT);
  cv::Sobel(smooth, gy, CV_32F, 0, 1, 3, 0.125, 0.0, cv::BORDER_REFLECT);
  cv::magnitude(gx, gy, magnitude);
  return magnitude;
}

double mean_edge_strength(const cv::Mat& edges) { return cv::mean(edges)[0]; }

double map_self_similarity(const cv::Mat& window, cv::Point at, int size) {
  if (size <= 0 || at.x < 0 || at.y < 0 || at.x + size > window.cols || at.y + size > window.rows) return -1.0;
  const cv::Mat patch = window(cv::Rect(at.x, at.y, size, size)).clone();
  cv::Mat surface;
  cv::matchTemplate(window, patch, surface, cv::TM_CCOEFF_NORMED);
  int within = 0;
  return best_rival(surface, at, half_peak_radius(surface, at), &within);
}

double texture_stddev(const cv::Mat& grey, const cv::Mat& valid) {
  cv::Scalar mean, stddev;
  cv::meanStdDev(grey, mean, stddev, valid);
  return stddev[0];
}

Registration register_template(const cv::Mat& window, const cv::Mat& templ) {
  Registration out;
  if (window.empty() || templ.empty() || window.rows < templ.rows || window.cols < templ.cols) return out;
  cv::Mat surface;
  cv::matchTemplate(window, templ, surface, cv::TM_CCOEFF_NORMED);
  double best = 0.0;
  cv::Point peak;
  cv::minMaxLoc(surface, nullptr, &best, nullptr, &peak);
  if (!std::isfinite(best)) return out;
  out.found = true;
  out.score = best;
  out.peak_px = peak;
  const int w = surface.cols, h = surface.rows;
  out.at_edge = peak.x == 0 || peak.y == 0 || peak.x == w - 1 || peak.y == h - 1;
  out.lobe_pixels = 0;
  out.second_score = best_rival(surface, peak, half_peak_radius(surface, peak), &out.lobe_pixels);
  out.peak_ratio = best / std::max(out.second_score, 0.01);

  double dx = 0.0, dy = 0.0;
  if (!out.at_edge) {
    auto s = [&](int x, int y) { return static_cast<double>(surface.at<float>(y, x)); };
    const double c = s(peak.x, peak.y);
    const double l = s(peak.x - 1, peak.y), r = s(peak.x + 1, peak.y);
    const double u = s(peak.x, peak.y - 1), d = s(peak.x, peak.y + 1);
    dx = parabola_vertex(l, c, r);
    dy = parabola_vertex(u, c, d);
    out.hessian(0, 0) = l - 2.0 * c + r;
    out.hessian(1, 1) = u - 2.0 * c + d;
    out.hessian(0, 1) = out.hessian(1, 0) =
        0.25 * (s(peak.x + 1, peak.y + 1) - s(peak.x + 1, peak.y - 1) - s(peak.x - 1, peak.y + 1) +
                s(peak.x - 1, peak.y - 1));
  }
  out.shift_px = {peak.x + dx - 0.5 * (w - 1), peak.y + dy - 0.5 * (h - 1)};
  return out;
}

}  // namespace nadir
