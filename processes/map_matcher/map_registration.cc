#include "processes/map_matcher/map_registration.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace nadir {

namespace {

// Marks the peak's lobe: pixels 4-connected to it whose score is above half the peak.
int mark_lobe(const cv::Mat& surface, cv::Point peak, cv::Mat* lobe) {
  const float threshold = 0.5f * surface.at<float>(peak);
  *lobe = cv::Mat::zeros(surface.size(), CV_8U);
  std::vector<cv::Point> stack{peak};
  lobe->at<uint8_t>(peak) = 1;
  int count = 0;
  while (!stack.empty()) {
    const cv::Point p = stack.back();
    stack.pop_back();
    ++count;
    const cv::Point next[4] = {{p.x + 1, p.y}, {p.x - 1, p.y}, {p.x, p.y + 1}, {p.x, p.y - 1}};
    for (const cv::Point& q : next) {
      if (q.x < 0 || q.y < 0 || q.x >= surface.cols || q.y >= surface.rows) continue;
      if (lobe->at<uint8_t>(q) || surface.at<float>(q) <= threshold) continue;
      lobe->at<uint8_t>(q) = 1;
      stack.push_back(q);
    }
  }
  return count;
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
  const int w = surface.cols, h = surface.rows;
  out.at_edge = peak.x == 0 || peak.y == 0 || peak.x == w - 1 || peak.y == h - 1;
  cv::Mat lobe;
  out.lobe_pixels = mark_lobe(surface, peak, &lobe);
  // Second best: outside the lobe grown by one pixel.
  cv::dilate(lobe, lobe, cv::Mat::ones(3, 3, CV_8U));
  double second = -1.0;
  cv::minMaxLoc(surface, nullptr, &second, nullptr, nullptr, lobe == 0);
  out.second_score = cv::countNonZero(lobe == 0) > 0 ? second : -1.0;
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
