#pragma once
// Pyramidal Lucas-Kanade, one point at a time, on float image pyramids.
//
// The method is cv::calcOpticalFlowPyrLK's (translation only; the window's
// gradients from a Scharr filter; inverse-compositional Gauss-Newton steps
// until a step is shorter than epsilon; half a step back and stop when two
// steps cancel; a track is lost when the window's minimum eigenvalue is below
// the threshold, in OpenCV's units, or the window leaves the image at full
// resolution), with the same options and the same meaning of the patch error.
// What differs is the arithmetic: float samples instead of 14-bit fixed point,
// and window rows processed in blocks of 8 lanes, so a 21-pixel row is three
// blocks instead of OpenCV 4.6's 16 SIMD pixels plus 5 scalar ones.
//
// Reproducible bit for bit on any instruction set: every lane adds its terms
// in a fixed order, the lanes are added in a fixed order, and nothing is
// fused (the file is built with -ffp-contract=off), so the AVX2 clone of the
// window loops and the SSE2 (or NEON) code give identical results.

#include <opencv2/core.hpp>

#include <vector>

namespace nadir {

// An image pyramid (cv::pyrDown, as OpenCV's KLT builds it) stored as float
// with a mirrored border (BORDER_REFLECT_101) around every level, wide enough
// for any window the tracker may place partly outside the image.
class LkPyramid {
 public:
  // `image`: CV_8UC1. `levels` >= 1 (full resolution included); `border`:
  // pixels of margin on every side (LucasKanade::border_for()).
  void build(const cv::Mat& image, int levels, int border);
  void clear() { levels_.clear(); }
  bool empty() const { return levels_.empty(); }
  int levels() const { return static_cast<int>(levels_.size()); }
  int border() const { return border_; }
  // Level i without its border.
  cv::Size size(int i) const { return sizes_[static_cast<size_t>(i)]; }
  // Pointer to pixel (0, 0) of level i; rows are stride(i) floats apart, and
  // `border` pixels to every side are readable.
  const float* origin(int i) const;
  size_t stride(int i) const { return levels_[static_cast<size_t>(i)].step1(); }
  void swap(LkPyramid& other);

 private:
  std::vector<cv::Mat> levels_;  // CV_32F, border included
  std::vector<cv::Size> sizes_;
  int border_ = 0;
  std::vector<cv::Mat> gray_;    // 8-bit levels above full resolution
  cv::Mat padded_;               // reused between frames
};

struct LkOptions {
  int window_px = 21;              // square window, >= 3
  int max_iterations = 30;         // per level
  double epsilon_px = 0.01;        // stop when a step is shorter than this
  double min_eig_threshold = 1e-4; // as cv::calcOpticalFlowPyrLK's minEigThreshold
};

class LucasKanade {
 public:
  explicit LucasKanade(const LkOptions& options);

  // The pyramid border that every window of `window_px` (or smaller) needs.
  static int border_for(int window_px);

  // Tracks `prev_px` (level-0 pixels of `prev`) into `curr`, starting from
  // *next_px, through levels max_level..0 (max_level < both pyramids'
  // levels()). On return *next_px is where it went. False when the track is
  // lost at full resolution: too little texture (minimum eigenvalue) or a
  // window outside the image. `patch_error`, when given, receives the mean
  // absolute grey-level difference between the two windows at the end.
  // `warp`, when given, is the window's expected deformation at full
  // resolution: offsets around the feature in `curr` = warp * offsets around
  // it in `prev` (lens and camera motion make a window that is a square in one
  // image a slightly sheared, scaled, rotated one in the other). The template
  // is then resampled through it, so the translation that is solved for is
  // the feature's own, not one biased by the deformation. Each element of
  // warp - identity must lie within +-kMaxWarpDeviation (std::invalid_argument
  // otherwise).
  bool track(const LkPyramid& prev, const LkPyramid& curr, cv::Point2f prev_px, cv::Point2f* next_px, int max_level,
             float* patch_error, const cv::Matx22f* warp = nullptr);

  static constexpr float kMaxWarpDeviation = 0.2f;
  // True when every element of warp - identity is within +-bound (NaN: false).
  static bool warp_within(const cv::Matx22d& warp, double bound);

 private:
  // Samples the window around top-left `corner` of `prev` level `level` and
  // its gradients; false when the window is too far outside the image.
  bool load_template(const LkPyramid& prev, int level, cv::Point2f corner);
  // The same with the patch sampled through `inverse_warp` (prev offsets per
  // curr offset) about `centre` (level-0 pixels of `prev`).
  bool load_warped_template(const LkPyramid& prev, cv::Point2f centre, cv::Point2f corner,
                            const cv::Matx22f& inverse_warp);
  // Template gradients and structure tensor from patch_.
  void template_from_patch();
  // The window at `corner`, whose top-left pixel is (ix, iy), against the template.
  float mean_abs_difference(const LkPyramid& curr, int level, cv::Point2f corner, int ix, int iy) const;

  LkOptions options_;
  int window_;
  int blocks_;        // 8-lane blocks per window row
  int lanes_;         // blocks_ * 8: floats per stored window row
  int patch_cols_;    // columns of the sampled patch: lanes_ + one block
  // The template window (rows x lanes_, zero gradient in padding lanes) and
  // the patch one pixel wider on every side that its gradients come from.
  std::vector<float> patch_, templ_, grad_x_, grad_y_;
  std::vector<float> lane_mask_;  // lanes_ floats: 1 inside the window, 0 beyond
  double a11_ = 0, a12_ = 0, a22_ = 0;  // structure tensor of the template
};

}  // namespace nadir
