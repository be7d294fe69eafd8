#include "processes/tracker/lucas_kanade.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

namespace nadir {

namespace {

constexpr int kLanes = 8;

// Eight floats that the compiler maps onto whatever vector registers the
// target has (two SSE2 or NEON registers, one AVX register). Lane-wise IEEE
// arithmetic in program order: the same bits on every target.
typedef float Lanes8 __attribute__((vector_size(kLanes * sizeof(float))));

// On x86-64 the window loops also get an AVX2 clone, chosen at load time
// (not under AddressSanitizer, so that build runs the plain code path).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define NADIR_LK_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define NADIR_LK_CLONES
#endif
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#include <immintrin.h>
#define NADIR_LK_GATHER 1
#endif

int round_up_to_lanes(int n) { return (n + kLanes - 1) / kLanes * kLanes; }

// OpenCV's rule for a window's top-left pixel: usable while it is at most a
// window outside the image. Compared as floats first, so that a diverged
// (huge or NaN) position is out of range rather than an integer overflow.
bool window_corner(cv::Point2f corner, int window, cv::Size size, int* ix, int* iy) {
  const float w = static_cast<float>(window);
  if (!(corner.x >= -w && corner.x < static_cast<float>(size.width) && corner.y >= -w &&
        corner.y < static_cast<float>(size.height)))
    return false;
  *ix = static_cast<int>(std::floor(corner.x));
  *iy = static_cast<int>(std::floor(corner.y));
  return true;
}

// Weights of the four neighbours for a window whose top-left corner lies at
// `corner`, in the pixel square starting at (ix, iy).
struct BilinearWeights {
  float w00, w01, w10, w11;
  BilinearWeights(cv::Point2f corner, int ix, int iy)
      : BilinearWeights(corner.x - static_cast<float>(ix), corner.y - static_cast<float>(iy)) {}

 private:
  BilinearWeights(float a, float b)
      : w00((1.f - a) * (1.f - b)), w01(a * (1.f - b)), w10((1.f - a) * b), w11(a * b) {}
};

// Eight consecutive bilinear samples starting at column c of the row pair
// (p0, p1). Written through a pointer: a vector returned by value would
// depend on the vector ABI of the caller's target.
__attribute__((always_inline)) inline void bilinear8(const float* p0, const float* p1, int c, const BilinearWeights& w,
                                                    Lanes8* out) {
  Lanes8 a, b, cc, d;
  std::memcpy(&a, p0 + c, sizeof a);
  std::memcpy(&b, p0 + c + 1, sizeof b);
  std::memcpy(&cc, p1 + c, sizeof cc);
  std::memcpy(&d, p1 + c + 1, sizeof d);
  *out = a * w.w00 + b * w.w01 + cc * w.w10 + d * w.w11;
}

// Bilinear samples of `rows` x (8 * blocks) pixels starting at `src` (the
// top-left integer pixel) into `dst` (rows of 8 * blocks floats).
NADIR_LK_CLONES
void sample_block_rows(const float* src, size_t stride, int rows, int blocks, const BilinearWeights& w, float* dst) {
  for (int r = 0; r < rows; ++r) {
    const float* p0 = src + static_cast<size_t>(r) * stride;
    const float* p1 = p0 + stride;
    for (int k = 0; k < blocks; ++k) {
      Lanes8 v;
      bilinear8(p0, p1, k * kLanes, w, &v);
      std::memcpy(dst + (static_cast<size_t>(r) * blocks + k) * kLanes, &v, sizeof v);
    }
  }
}

// The image mismatch of one Gauss-Newton step: sum over the window of
// (J(x + corner) - T(x)) * grad T(x), with J bilinear at the corner's
// fraction. Padding lanes have zero gradient and add nothing.
NADIR_LK_CLONES
void mismatch_sums(const float* j, size_t stride, const float* templ, const float* grad_x, const float* grad_y,
                   int rows, int blocks, const BilinearWeights& w, float* sum_x, float* sum_y) {
  Lanes8 sx = {}, sy = {};
  for (int r = 0; r < rows; ++r) {
    const float* p0 = j + static_cast<size_t>(r) * stride;
    const float* p1 = p0 + stride;
    const size_t row = static_cast<size_t>(r) * static_cast<size_t>(blocks) * kLanes;
    for (int k = 0; k < blocks; ++k) {
      Lanes8 v, t, gx, gy;
      bilinear8(p0, p1, k * kLanes, w, &v);
      std::memcpy(&t, templ + row + k * kLanes, sizeof t);
      std::memcpy(&gx, grad_x + row + k * kLanes, sizeof gx);
      std::memcpy(&gy, grad_y + row + k * kLanes, sizeof gy);
      const Lanes8 diff = v - t;
      sx += diff * gx;
      sy += diff * gy;
    }
  }
  float x = 0.f, y = 0.f;
  for (int l = 0; l < kLanes; ++l) {
    x += sx[l];
    y += sy[l];
  }
  *sum_x = x;
  *sum_y = y;
}

// The template window (rows x 8 * blocks) and its Scharr gradients (3-10-3
// smoothing across a central difference, divided by 32: grey levels per
// pixel) from a patch sampled one pixel wider on every side, as OpenCV takes
// them from the level image before interpolating. Lanes where `mask` is 0
// get zero gradient, so they add nothing to any sum. lane_sums: 8 lanes each
// of sum gx^2, gx*gy, gy^2.
NADIR_LK_CLONES
void template_gradients(const float* patch, size_t patch_cols, int rows, int blocks, const float* mask_lanes,
                        float* templ, float* grad_x, float* grad_y, float* lane_sums) {
  Lanes8 s11 = {}, s12 = {}, s22 = {};
  for (int r = 0; r < rows; ++r) {
    const float* up = patch + static_cast<size_t>(r) * patch_cols;
    const float* mid = up + patch_cols;
    const float* down = mid + patch_cols;
    const size_t row = static_cast<size_t>(r) * static_cast<size_t>(blocks) * kLanes;
    for (int k = 0; k < blocks; ++k) {
      const int c = k * kLanes;
      Lanes8 u0, u1, u2, m0, m1, m2, d0, d1, d2, mask;
      std::memcpy(&u0, up + c, sizeof u0);
      std::memcpy(&u1, up + c + 1, sizeof u1);
      std::memcpy(&u2, up + c + 2, sizeof u2);
      std::memcpy(&m0, mid + c, sizeof m0);
      std::memcpy(&m1, mid + c + 1, sizeof m1);
      std::memcpy(&m2, mid + c + 2, sizeof m2);
      std::memcpy(&d0, down + c, sizeof d0);
      std::memcpy(&d1, down + c + 1, sizeof d1);
      std::memcpy(&d2, down + c + 2, sizeof d2);
      std::memcpy(&mask, mask_lanes + c, sizeof mask);
      const Lanes8 gx = (3.f * (u2 - u0) + 10.f * (m2 - m0) + 3.f * (d2 - d0)) * (1.f / 32.f) * mask;
      const Lanes8 gy = (3.f * (d0 - u0) + 10.f * (d1 - u1) + 3.f * (d2 - u2)) * (1.f / 32.f) * mask;
      std::memcpy(templ + row + c, &m1, sizeof m1);
      std::memcpy(grad_x + row + c, &gx, sizeof gx);
      std::memcpy(grad_y + row + c, &gy, sizeof gy);
      s11 += gx * gx;
      s12 += gx * gy;
      s22 += gy * gy;
    }
  }
  std::memcpy(lane_sums, &s11, sizeof s11);
  std::memcpy(lane_sums + kLanes, &s12, sizeof s12);
  std::memcpy(lane_sums + 2 * kLanes, &s22, sizeof s22);
}

// Per lane, the sum of |J - T| over the window (lanes where `mask` is 0 add
// nothing), J bilinear at the corner's fraction.
NADIR_LK_CLONES
void abs_difference_sums(const float* j, size_t stride, const float* templ, const float* mask_lanes, int rows,
                         int blocks, const BilinearWeights& w, float* lane_sums) {
  typedef int32_t Bits8 __attribute__((vector_size(kLanes * sizeof(int32_t))));
  const Bits8 magnitude = Bits8{} + 0x7fffffff;  // all but the sign bit
  Lanes8 sum = {};
  for (int r = 0; r < rows; ++r) {
    const float* p0 = j + static_cast<size_t>(r) * stride;
    const float* p1 = p0 + stride;
    const size_t row = static_cast<size_t>(r) * static_cast<size_t>(blocks) * kLanes;
    for (int k = 0; k < blocks; ++k) {
      const int c = k * kLanes;
      Lanes8 v, t, mask, abs_diff;
      bilinear8(p0, p1, c, w, &v);
      std::memcpy(&t, templ + row + c, sizeof t);
      std::memcpy(&mask, mask_lanes + c, sizeof mask);
      const Lanes8 diff = v - t;
      Bits8 bits;
      std::memcpy(&bits, &diff, sizeof bits);
      bits &= magnitude;
      std::memcpy(&abs_diff, &bits, sizeof abs_diff);
      sum += abs_diff * mask;
    }
  }
  std::memcpy(lane_sums, &sum, sizeof sum);
}


// The patch of a warped template: rows x cols bilinear samples (cols =
// rows = window + 2) at offsets from `centre` mapped through `inverse_warp`,
// each row padded with zeros to patch_cols (the deviation bound keeps every
// read inside the pyramid's border).
void sample_warped_rows_scalar(const float* origin, size_t stride, cv::Point2f centre,
                               const cv::Matx22f& inverse_warp, int window, int patch_cols, float* patch) {
  const float half = static_cast<float>(window - 1) * 0.5f;
  const int cols = window + 2;
  // floor() without a library call (SSE2 has no rounding instruction); exact.
  auto floor_int = [](float v) {
    const int t = static_cast<int>(v);
    return static_cast<float>(t) > v ? t - 1 : t;
  };
  for (int r = 0; r < cols; ++r) {
    float* row = patch + static_cast<size_t>(r) * static_cast<size_t>(patch_cols);
    const float oy = static_cast<float>(r - 1) - half;
    const float row_x = centre.x + inverse_warp(0, 1) * oy, row_y = centre.y + inverse_warp(1, 1) * oy;
    for (int k = 0; k < cols; ++k) {
      const float ox = static_cast<float>(k - 1) - half;
      const float x = row_x + inverse_warp(0, 0) * ox;
      const float y = row_y + inverse_warp(1, 0) * ox;
      const int sx = floor_int(x), sy = floor_int(y);
      const float a = x - static_cast<float>(sx), b = y - static_cast<float>(sy);
      const float* p0 = origin + static_cast<ptrdiff_t>(sy) * static_cast<ptrdiff_t>(stride) + sx;
      const float* p1 = p0 + stride;
      row[k] = (1.f - a) * (1.f - b) * p0[0] + a * (1.f - b) * p0[1] + (1.f - a) * b * p1[0] + a * b * p1[1];
    }
    std::fill(row + cols, row + patch_cols, 0.f);  // beyond the window: masked lanes
  }
}

#ifdef NADIR_LK_GATHER
// Eight pairs of neighbouring floats (p[offset[l]], p[offset[l] + 1]),
// split into the first of each pair (*first, lane l) and the second
// (*second): 8-byte loads and one shuffle (an AVX2 gather is several times
// slower on some processors). Lanes from `valid` on read lane 0's pair.
__attribute__((target("avx2"))) inline void load_pairs(const float* p, __m256i offset, int valid, __m256* first,
                                                       __m256* second) {
  if (valid < kLanes) {
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    offset = _mm256_blendv_epi8(_mm256_set1_epi32(_mm256_extract_epi32(offset, 0)), offset,
                                _mm256_cmpgt_epi32(_mm256_set1_epi32(valid), lane));
  }
  const __m128i lo = _mm256_castsi256_si128(offset), hi = _mm256_extracti128_si256(offset, 1);
  auto two_pairs = [p](int i, int j) {
    const __m128 v = _mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(p + i));
    return _mm_loadh_pi(v, reinterpret_cast<const __m64*>(p + j));
  };
  // Lanes 0, 1, 4, 5 and 2, 3, 6, 7 as pairs: the shuffle puts them back in order.
  const __m256 a = _mm256_set_m128(two_pairs(_mm_extract_epi32(hi, 0), _mm_extract_epi32(hi, 1)),
                                   two_pairs(_mm_extract_epi32(lo, 0), _mm_extract_epi32(lo, 1)));
  const __m256 b = _mm256_set_m128(two_pairs(_mm_extract_epi32(hi, 2), _mm_extract_epi32(hi, 3)),
                                   two_pairs(_mm_extract_epi32(lo, 2), _mm_extract_epi32(lo, 3)));
  *first = _mm256_shuffle_ps(a, b, 0x88);
  *second = _mm256_shuffle_ps(a, b, 0xDD);
}

// The same, eight columns at a time: each lane the same IEEE operations in
// the same order as the scalar sample (no fused multiply-add), so the same
// bits.
__attribute__((target("avx2"))) void sample_warped_rows_avx2(const float* origin, size_t stride, cv::Point2f centre,
                                                             const cv::Matx22f& inverse_warp, int window,
                                                             int patch_cols, float* patch) {
  typedef int32_t Ints8 __attribute__((vector_size(kLanes * sizeof(int32_t))));
  const float half = static_cast<float>(window - 1) * 0.5f;
  const int cols = window + 2;
  const int row_step = static_cast<int>(stride);
  const Lanes8 one = Lanes8{} + 1.f;
  const Ints8 lane = {0, 1, 2, 3, 4, 5, 6, 7};
  for (int r = 0; r < cols; ++r) {
    float* row = patch + static_cast<size_t>(r) * static_cast<size_t>(patch_cols);
    const float oy = static_cast<float>(r - 1) - half;
    const float row_x = centre.x + inverse_warp(0, 1) * oy, row_y = centre.y + inverse_warp(1, 1) * oy;
    for (int c = 0; c < cols; c += kLanes) {
      const int valid = std::min(kLanes, cols - c);
      const Lanes8 ox = __builtin_convertvector(lane + (c - 1), Lanes8) - half;
      const Lanes8 x = row_x + inverse_warp(0, 0) * ox;
      const Lanes8 y = row_y + inverse_warp(1, 0) * ox;
      // floor() as truncation, one less where that rounded up: exact.
      Ints8 sx = __builtin_convertvector(x, Ints8), sy = __builtin_convertvector(y, Ints8);
      sx += __builtin_convertvector(sx, Lanes8) > x;  // a true comparison is -1
      sy += __builtin_convertvector(sy, Lanes8) > y;
      const Lanes8 a = x - __builtin_convertvector(sx, Lanes8), b = y - __builtin_convertvector(sy, Lanes8);
      const __m256i offset = (__m256i)(sy * row_step + sx);
      __m256 p00, p01, p10, p11;
      load_pairs(origin, offset, valid, &p00, &p01);
      load_pairs(origin + stride, offset, valid, &p10, &p11);
      const Lanes8 v = (one - a) * (one - b) * (Lanes8)p00 + a * (one - b) * (Lanes8)p01 +
                       (one - a) * b * (Lanes8)p10 + a * b * (Lanes8)p11;
      std::memcpy(row + c, &v, sizeof(float) * static_cast<size_t>(valid));
    }
    std::fill(row + cols, row + patch_cols, 0.f);  // beyond the window: masked lanes
  }
}
#endif

void sample_warped_rows(const float* origin, size_t stride, cv::Point2f centre, const cv::Matx22f& inverse_warp,
                        int window, int patch_cols, float* patch) {
#ifdef NADIR_LK_GATHER
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) return sample_warped_rows_avx2(origin, stride, centre, inverse_warp, window, patch_cols, patch);
#endif
  sample_warped_rows_scalar(origin, stride, centre, inverse_warp, window, patch_cols, patch);
}

}  // namespace

void LkPyramid::build(const cv::Mat& image, int levels, int border) {
  if (image.empty() || image.type() != CV_8UC1)
    throw std::invalid_argument("LkPyramid::build needs an 8-bit mono image");
  if (levels < 1 || border < 1) throw std::invalid_argument("LkPyramid::build: levels and border must be >= 1");
  border_ = border;
  levels_.resize(static_cast<size_t>(levels));
  sizes_.resize(static_cast<size_t>(levels));
  gray_.resize(static_cast<size_t>(levels));
  for (size_t i = 0; i < levels_.size(); ++i) {
    if (i > 0) {
      const cv::Mat& finer = i == 1 ? image : gray_[i - 1];
      cv::pyrDown(finer, gray_[i], cv::Size((finer.cols + 1) / 2, (finer.rows + 1) / 2), cv::BORDER_REFLECT_101);
    }
    const cv::Mat& level = i == 0 ? image : gray_[i];
    sizes_[i] = level.size();
    cv::copyMakeBorder(level, padded_, border, border, border, border, cv::BORDER_REFLECT_101);
    padded_.convertTo(levels_[i], CV_32F);
  }
}

const float* LkPyramid::origin(int i) const {
  const cv::Mat& m = levels_[static_cast<size_t>(i)];
  return m.ptr<float>(border_) + border_;
}

void LkPyramid::swap(LkPyramid& other) {
  std::swap(levels_, other.levels_);
  std::swap(sizes_, other.sizes_);
  std::swap(border_, other.border_);
}

LucasKanade::LucasKanade(const LkOptions& options)
    : options_(options),
      window_(options.window_px),
      blocks_(round_up_to_lanes(options.window_px) / kLanes),
      lanes_(round_up_to_lanes(options.window_px)),
      patch_cols_(round_up_to_lanes(options.window_px) + kLanes) {
  if (window_ < 3) throw std::invalid_argument("LucasKanade: window_px must be >= 3, got " + std::to_string(window_));
  if (options.max_iterations < 1) throw std::invalid_argument("LucasKanade: max_iterations must be >= 1");
  patch_.assign(static_cast<size_t>((window_ + 2) * patch_cols_), 0.f);
  lane_mask_.assign(static_cast<size_t>(lanes_), 0.f);
  std::fill(lane_mask_.begin(), lane_mask_.begin() + window_, 1.f);
  const size_t window_floats = static_cast<size_t>(window_ * lanes_);
  templ_.assign(window_floats, 0.f);
  grad_x_.assign(window_floats, 0.f);
  grad_y_.assign(window_floats, 0.f);
}

bool LucasKanade::warp_within(const cv::Matx22d& warp, double bound) {
  for (int k = 0; k < 4; ++k)
    if (!(std::fabs(warp.val[k] - (k == 0 || k == 3 ? 1.0 : 0.0)) <= bound)) return false;
  return true;
}

int LucasKanade::border_for(int window_px) {
  // Top-left pixels as far as a window outside, plus what the patch (from one
  // pixel before the window, whole 8-lane blocks and one more block for the
  // derivatives' neighbours) reads beyond the window, plus the bilinear
  // neighbour. A warped template reaches from the window's centre (half a
  // window outside at most) as far as the inverse of a warp within
  // kMaxWarpDeviation takes the patch's corners: under 1.7 times their offset.
  const int translated = std::max(window_px + 1, round_up_to_lanes(window_px) + kLanes) + 2;
  const double half = 0.5 * window_px;
  const int warped = static_cast<int>(std::ceil(half + 1.7 * (half + 1.0))) + 2;
  return std::max(translated, warped);
}

bool LucasKanade::load_template(const LkPyramid& prev, int level, cv::Point2f corner) {
  int ix = 0, iy = 0;
  if (!window_corner(corner, window_, prev.size(level), &ix, &iy)) return false;
  const size_t stride = prev.stride(level);
  const float* src = prev.origin(level) + static_cast<ptrdiff_t>(iy - 1) * static_cast<ptrdiff_t>(stride) + (ix - 1);
  const BilinearWeights w(corner, ix, iy);
  sample_block_rows(src, stride, window_ + 2, patch_cols_ / kLanes, w, patch_.data());
  template_from_patch();
  return true;
}

bool LucasKanade::load_warped_template(const LkPyramid& prev, cv::Point2f centre, cv::Point2f corner,
                                       const cv::Matx22f& inverse_warp) {
  int ix = 0, iy = 0;
  if (!window_corner(corner, window_, prev.size(0), &ix, &iy)) return false;
  sample_warped_rows(prev.origin(0), prev.stride(0), centre, inverse_warp, window_, patch_cols_, patch_.data());
  template_from_patch();
  return true;
}

void LucasKanade::template_from_patch() {
  float lane_sums[3 * kLanes];
  template_gradients(patch_.data(), static_cast<size_t>(patch_cols_), window_, blocks_, lane_mask_.data(),
                     templ_.data(), grad_x_.data(), grad_y_.data(), lane_sums);
  a11_ = a12_ = a22_ = 0.0;
  for (int l = 0; l < kLanes; ++l) {
    a11_ += static_cast<double>(lane_sums[l]);
    a12_ += static_cast<double>(lane_sums[kLanes + l]);
    a22_ += static_cast<double>(lane_sums[2 * kLanes + l]);
  }
}

float LucasKanade::mean_abs_difference(const LkPyramid& curr, int level, cv::Point2f corner, int ix, int iy) const {
  const size_t stride = curr.stride(level);
  const BilinearWeights w(corner, ix, iy);
  float lane_sums[kLanes];
  abs_difference_sums(curr.origin(level) + static_cast<ptrdiff_t>(iy) * static_cast<ptrdiff_t>(stride) + ix, stride,
                      templ_.data(), lane_mask_.data(), window_, blocks_, w, lane_sums);
  double total = 0;
  for (int l = 0; l < kLanes; ++l) total += static_cast<double>(lane_sums[l]);
  return static_cast<float>(total / (window_ * window_));
}

bool LucasKanade::track(const LkPyramid& prev, const LkPyramid& curr, cv::Point2f prev_px, cv::Point2f* next_px,
                        int max_level, float* patch_error, const cv::Matx22f* warp) {
  if (max_level < 0 || max_level >= prev.levels() || max_level >= curr.levels())
    throw std::invalid_argument("LucasKanade::track: max_level " + std::to_string(max_level) + " beyond the pyramids");
  if (prev.border() < border_for(window_) || curr.border() < border_for(window_))
    throw std::invalid_argument("LucasKanade::track: pyramid border below border_for(" + std::to_string(window_) + ")");
  cv::Matx22f inverse_warp;
  if (warp) {
    const cv::Matx22f& a = *warp;
    if (!warp_within(cv::Matx22d(a), kMaxWarpDeviation))
      throw std::invalid_argument("LucasKanade::track: warp (" + std::to_string(a(0, 0)) + ", " +
                                  std::to_string(a(0, 1)) + "; " + std::to_string(a(1, 0)) + ", " +
                                  std::to_string(a(1, 1)) + ") deviates from identity by more than " +
                                  std::to_string(kMaxWarpDeviation));
    const double det = static_cast<double>(a(0, 0)) * a(1, 1) - static_cast<double>(a(0, 1)) * a(1, 0);
    inverse_warp = cv::Matx22f(static_cast<float>(a(1, 1) / det), static_cast<float>(-a(0, 1) / det),
                               static_cast<float>(-a(1, 0) / det), static_cast<float>(a(0, 0) / det));
  }
  const float half = static_cast<float>(window_ - 1) * 0.5f;
  const cv::Point2f half_win(half, half);
  const double epsilon_sq = options_.epsilon_px * options_.epsilon_px;
  // OpenCV's structure tensor is in (32 x gradient)^2 / 2^20 units.
  const double cv_units = 1.0 / 1024.0;
  const double window_area = static_cast<double>(window_) * window_;
  cv::Point2f next = *next_px * (1.f / static_cast<float>(1 << max_level));
  for (int level = max_level; level >= 0; --level) {
    if (level != max_level) next *= 2.f;
    const cv::Point2f corner = prev_px * (1.f / static_cast<float>(1 << level)) - half_win;
    const bool loaded = warp && level == 0 ? load_warped_template(prev, prev_px, corner, inverse_warp)
                                           : load_template(prev, level, corner);
    if (!loaded) {
      if (level == 0) return false;
      continue;
    }
    const double a11 = a11_ * cv_units, a12 = a12_ * cv_units, a22 = a22_ * cv_units;
    const double det = a11 * a22 - a12 * a12;
    const double min_eig = (a22 + a11 - std::sqrt((a11 - a22) * (a11 - a22) + 4.0 * a12 * a12)) / (2.0 * window_area);
    if (min_eig < options_.min_eig_threshold || det < static_cast<double>(FLT_EPSILON)) {
      if (level == 0) return false;
      continue;
    }
    const double inv_det = 1.0 / (a11_ * a22_ - a12_ * a12_);
    const cv::Size size = curr.size(level);
    const size_t stride = curr.stride(level);
    cv::Point2f next_corner = next - half_win;
    cv::Point2f prev_delta;
    for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
      int ix = 0, iy = 0;
      if (!window_corner(next_corner, window_, size, &ix, &iy)) {
        if (level == 0) {
          *next_px = next;
          return false;
        }
        break;
      }
      const BilinearWeights w(next_corner, ix, iy);
      float bx = 0.f, by = 0.f;
      mismatch_sums(curr.origin(level) + static_cast<ptrdiff_t>(iy) * static_cast<ptrdiff_t>(stride) + ix, stride,
                    templ_.data(), grad_x_.data(), grad_y_.data(), window_, blocks_, w, &bx, &by);
      const cv::Point2f delta(static_cast<float>((a12_ * by - a22_ * bx) * inv_det),
                              static_cast<float>((a12_ * bx - a11_ * by) * inv_det));
      next_corner += delta;
      next = next_corner + half_win;
      if (static_cast<double>(delta.dot(delta)) <= epsilon_sq) break;
      if (iteration > 0 && std::fabs(delta.x + prev_delta.x) < 0.01f && std::fabs(delta.y + prev_delta.y) < 0.01f) {
        next -= delta * 0.5f;  // oscillating: settle between the two
        break;
      }
      prev_delta = delta;
    }
  }
  *next_px = next;
  const cv::Point2f end_corner = next - half_win;
  int ex = 0, ey = 0;
  if (!window_corner(end_corner, window_, curr.size(0), &ex, &ey)) return false;
  if (patch_error) *patch_error = mean_abs_difference(curr, 0, end_corner, ex, ey);
  return true;
}

}  // namespace nadir
