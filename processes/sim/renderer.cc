#include "processes/sim/renderer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "processes/sim/procedural_noise.h"
#include "processes/sim/ray_caster.h"

namespace nadir::sim {
namespace {

// Sun from the south-east, 50 degrees up (north, east, up).
constexpr double kNoHit = -1e30;
const Eigen::Vector3d kSunNeu = Eigen::Vector3d(-0.45, 0.45, 0.766).normalized();

inline uint64_t splitmix(uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

void RendererOptions::Check() const {
  if (!(pixel_noise_dn >= 0.0 && pixel_noise_dn <= 50.0)) throw std::invalid_argument("pixel_noise_dn must be in [0, 50]");
  if (!(gain > 0.0 && gain <= 4.0)) throw std::invalid_argument("gain must be in (0, 4]");
  if (coarse_step_px < 2 || coarse_step_px > 64) throw std::invalid_argument("coarse_step_px must be in [2, 64]");
}

Renderer::Renderer(const SimCamera& camera, const Terrain& terrain, const RendererOptions& options)
    : camera_(camera), terrain_(terrain), options_(options), texture_(terrain) {
  options_.Check();
  const int w = camera_.width, h = camera_.height;
  std::vector<cv::Point2d> pixels;
  pixels.reserve(static_cast<size_t>(w) * h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) pixels.emplace_back(u, v);
  const std::vector<cv::Point2d> normalized = camera_.undistort(pixels);
  const size_t n = normalized.size();
  ray_x_.resize(n);
  ray_y_.resize(n);
  ray_z_.resize(n);
  pixel_angle_.resize(n);
  std::vector<Eigen::Vector3d> rays(n);
  for (size_t i = 0; i < n; ++i) {
    rays[i] = Eigen::Vector3d(normalized[i].x, normalized[i].y, 1.0).normalized();
    ray_x_[i] = static_cast<float>(rays[i].x());
    ray_y_[i] = static_cast<float>(rays[i].y());
    ray_z_[i] = static_cast<float>(rays[i].z());
  }
  // Angular size of each pixel (sqrt of its solid angle), for the texture footprint.
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const size_t i = static_cast<size_t>(v) * w + u;
      const size_t iu = static_cast<size_t>(v) * w + (u + 1 < w ? u + 1 : u - 1);
      const size_t iv = static_cast<size_t>(v + 1 < h ? v + 1 : v - 1) * w + u;
      pixel_angle_[i] = static_cast<float>(std::sqrt((rays[iu] - rays[i]).cross(rays[iv] - rays[i]).norm()));
    }
}

Eigen::Vector3d Renderer::pixel_ray(int u, int v) const {
  const size_t i = static_cast<size_t>(v) * camera_.width + u;
  return Eigen::Vector3d(ray_x_[i], ray_y_[i], ray_z_[i]);
}

double Renderer::block_slope(int gx, int gy, int gw, const Eigen::Vector3d& origin) {
  const int gh = static_cast<int>(coarse_dir_.size()) / gw;
  const size_t b = static_cast<size_t>(gy) * gw + gx;
  if (block_slope_[b] >= 0.0) return block_slope_[b];
  // The block's pixel rays lie within its four corner rays (up to the bow of
  // the lens distortion over 16 pixels: the margin). A ray's ground point at
  // depth k below the aircraft is origin + k * d_h / dz, so all the ground
  // they can cross for k in [0, k_end] lies in the box spanned by the
  // aircraft's nadir point and the corners' points at k_end.
  const int gx1 = std::min(gx + 1, gw - 1), gy1 = std::min(gy + 1, gh - 1);
  double sn0 = 1e18, sn1 = -1e18, se0 = 1e18, se1 = -1e18;
  bool downward = true;
  for (const int y : {gy, gy1})
    for (const int x : {gx, gx1}) {
      const Eigen::Vector3d& d = coarse_dir_[static_cast<size_t>(y) * gw + x];
      if (d.z() < 0.05) downward = false;
      sn0 = std::min(sn0, d.x() / d.z());
      sn1 = std::max(sn1, d.x() / d.z());
      se0 = std::min(se0, d.y() / d.z());
      se1 = std::max(se1, d.y() / d.z());
    }
  const double k_end = -origin.z() - terrain_.min_height() + 1.0;
  double slope = terrain_.max_slope();
  if (downward && k_end > 0.0) {
    const double margin_n = 0.05 * (sn1 - sn0) + 2e-3, margin_e = 0.05 * (se1 - se0) + 2e-3;
    sn0 -= margin_n;
    sn1 += margin_n;
    se0 -= margin_e;
    se1 += margin_e;
    const double n0 = origin.x() + std::min(0.0, k_end * sn0), n1 = origin.x() + std::max(0.0, k_end * sn1);
    const double e0 = origin.y() + std::min(0.0, k_end * se0), e1 = origin.y() + std::max(0.0, k_end * se1);
    // Flying high, a block's region covers many tiles: more to make and
    // scan than marching its pixels costs, so those keep the global bound.
    constexpr double kMaxRegionTiles = 100.0;
    const double tile = Terrain::kBoundsTileM;
    if ((n1 - n0 + tile) * (e1 - e0 + tile) <= kMaxRegionTiles * tile * tile)
      slope = std::min(slope, terrain_.bounds(n0, n1, e0, e1).max_slope);
  }
  block_slope_[b] = slope;
  return slope;
}

void Renderer::render(const Eigen::Vector3d& origin, const Eigen::Matrix3d& world_from_camera, uint64_t noise_key,
                      std::vector<uint8_t>* image) {
  const int w = camera_.width, h = camera_.height;
  image->assign(static_cast<size_t>(w) * h, 0);
  if (depth_out_) depth_out_->assign(static_cast<size_t>(w) * h, -1.0f);
  stats_ = RenderStats{};
  ++frame_;

  // 1. Exact hits on a coarse grid: seeds for per-pixel Newton, and the
  //    ground region whose texture tiles this frame needs.
  const int step = options_.coarse_step_px;
  const int gw = (w - 1 + step - 1) / step + 1, gh = (h - 1 + step - 1) / step + 1;
  coarse_t_.assign(static_cast<size_t>(gw) * gh, kNoHit);
  coarse_dir_.resize(static_cast<size_t>(gw) * gh);
  block_slope_.assign(static_cast<size_t>(gw) * gh, -1.0);
  double n0 = 1e18, n1 = -1e18, e0 = 1e18, e1 = -1e18;
  for (int gy = 0; gy < gh; ++gy)
    for (int gx = 0; gx < gw; ++gx) {
      const int u = std::min(gx * step, w - 1), v = std::min(gy * step, h - 1);
      const Eigen::Vector3d d = world_from_camera * pixel_ray(u, v);
      coarse_dir_[static_cast<size_t>(gy) * gw + gx] = d;
      RayHit hit;
      if (!cast_ray(terrain_, origin, d, -1.0, &hit)) continue;
      const Eigen::Vector3d p = origin + hit.t * d;
      // Stored as the hit's height: interpolating heights (not distances)
      // gives exact seeds on flat ground and near-exact ones on smooth relief.
      coarse_t_[static_cast<size_t>(gy) * gw + gx] = -p.z();
      n0 = std::min(n0, p.x());
      n1 = std::max(n1, p.x());
      e0 = std::min(e0, p.y());
      e1 = std::max(e1, p.y());
    }
  if (n0 <= n1) texture_.prepare(n0 - 8.0, n1 + 8.0, e0 - 8.0, e1 + 8.0, frame_);

  const double r00 = world_from_camera(0, 0), r01 = world_from_camera(0, 1), r02 = world_from_camera(0, 2);
  const double r10 = world_from_camera(1, 0), r11 = world_from_camera(1, 1), r12 = world_from_camera(1, 2);
  const double r20 = world_from_camera(2, 0), r21 = world_from_camera(2, 1), r22 = world_from_camera(2, 2);
  const double altitude = -origin.z();
  const double slope = terrain_.max_slope();
  // Rays steeper than the local slope bound meet the ground once even where
  // the global bound says they could be occluded; they end where the block's
  // bound region does (beyond it the ray is below all ground).
  const double region_end_depth = altitude - terrain_.min_height() + 1.0;
  const double noise_scale = options_.pixel_noise_dn / 147.80;  // sigma of a sum of 4 uniform bytes
  const float gain = static_cast<float>(options_.gain);

  for (int v = 0; v < h; ++v) {
    const int gy = v / step;
    const int v0 = gy * step, v1 = std::min((gy + 1) * step, h - 1);
    const double fy = v1 > v0 ? static_cast<double>(v - v0) / (v1 - v0) : 0.0;
    const int gy1 = std::min(gy + 1, gh - 1);
    uint8_t* row = image->data() + static_cast<size_t>(v) * w;
    for (int u = 0; u < w; ++u) {
      const size_t i = static_cast<size_t>(v) * w + u;
      const double cx = ray_x_[i], cy = ray_y_[i], cz = ray_z_[i];
      const Eigen::Vector3d d(r00 * cx + r01 * cy + r02 * cz, r10 * cx + r11 * cy + r12 * cz,
                              r20 * cx + r21 * cy + r22 * cz);
      // Seed from the coarse grid (bilinear in t).
      const int gx = u / step;
      const int u0 = gx * step, u1 = std::min((gx + 1) * step, w - 1);
      const double fx = u1 > u0 ? static_cast<double>(u - u0) / (u1 - u0) : 0.0;
      const int gx1 = std::min(gx + 1, gw - 1);
      const double t00 = coarse_t_[static_cast<size_t>(gy) * gw + gx], t01 = coarse_t_[static_cast<size_t>(gy) * gw + gx1];
      const double t10 = coarse_t_[static_cast<size_t>(gy1) * gw + gx], t11 = coarse_t_[static_cast<size_t>(gy1) * gw + gx1];
      const double dz = d.z();
      double t_guess = -1.0;
      if (t00 > kNoHit && t01 > kNoHit && t10 > kNoHit && t11 > kNoHit && dz > 1e-6) {
        const double h_seed = (t00 + (t01 - t00) * fx) * (1 - fy) + (t10 + (t11 - t10) * fx) * fy;
        t_guess = (altitude - h_seed) / dz;
      }

      const double dxy = std::sqrt(d.x() * d.x() + d.y() * d.y());
      double t = -1.0, gn = 0.0, ge = 0.0;
      // Monotone ray: f(t) = ray altitude - ground height strictly decreases
      // wherever the ray can meet the ground, so its one root is the first
      // hit. Globally (steeper than any slope anywhere), or locally (steeper
      // than every slope in the ground this block's rays cross from the
      // aircraft down to below the lowest ground).
      const bool monotone = slope * dxy < dz;
      const bool locally_monotone =
          !monotone && dz > 1e-6 && t_guess > 0 && block_slope(gx, gy, gw, origin) * dxy < dz;
      if (t_guess > 0 && dz > 1e-6 && (monotone || locally_monotone)) {
        // One Newton step from a good seed usually lands within
        // micrometres; otherwise fall back to the full safeguarded solve.
        // Up to three Newton steps; a step under 5 cm leaves an error of
        // ~curvature * dt^2: micrometres.
        double tn = t_guess;
        for (int it = 0; it < 3; ++it) {
          const double f = altitude - tn * dz - terrain_.height(origin.x() + tn * d.x(), origin.y() + tn * d.y(), &gn, &ge);
          const double df = -dz - gn * d.x() - ge * d.y();
          const double dt = -f / df;
          // Locally monotone: only from a point inside the bounded region.
          if (locally_monotone && !(tn >= 0.0 && tn * dz <= region_end_depth)) break;
          tn += dt;
          if (std::fabs(dt) < 0.05) {
            t = tn;
            if (locally_monotone) {
              // Shade with the gradient at the hit, as the marching path
              // does (the bilinear surface's gradient jumps across cells).
              terrain_.height(origin.x() + tn * d.x(), origin.y() + tn * d.y(), &gn, &ge);
              ++stats_.local_bound_pixels;
            }
            break;
          }
        }
      }
      if (t < 0) {
        ++stats_.full_solves;
        RayHit hit;
        if (cast_ray(terrain_, origin, d, t_guess, &hit)) {
          t = hit.t;
          gn = hit.dh_dn;
          ge = hit.dh_de;
          if (hit.marched) ++stats_.marched_pixels;
        }
      }
      if (depth_out_) (*depth_out_)[i] = static_cast<float>(t < 0 ? -1.0 : t);
      float value;
      if (t < 0) {
        ++stats_.sky_pixels;
        value = 250.0f;
      } else {
        const double pn = origin.x() + t * d.x(), pe = origin.y() + t * d.y();
        // Cosine between the ray and the surface normal; footprint grows as 1/sqrt(cos).
        const double norm = std::sqrt(1.0 + gn * gn + ge * ge);
        const double cos_inc = std::max(0.2, (dz + gn * d.x() + ge * d.y()) / norm);
        const double footprint = t * pixel_angle_[i] / std::sqrt(cos_inc);
        const float albedo = texture_.sample(pn, pe, footprint);
        const double shade = std::max(0.25, (-gn * kSunNeu.x() - ge * kSunNeu.y() + kSunNeu.z()) / (norm * kSunNeu.z()));
        value = albedo * static_cast<float>(shade) * gain;
        for (const GroundMarker& m : markers_) {
          const double dist = std::hypot(pn - m.north, pe - m.east);
          const double coverage = std::min(1.0, std::max(0.0, (m.radius_m - dist) / footprint + 0.5));
          value += static_cast<float>(coverage) * (m.value - value);
        }
      }
      if (noise_scale > 0) {
        const uint64_t r = splitmix(noise_key ^ (static_cast<uint64_t>(i) * 0xd1342543de82ef95ULL));
        const int sum = static_cast<int>(r & 0xff) + static_cast<int>((r >> 8) & 0xff) +
                        static_cast<int>((r >> 16) & 0xff) + static_cast<int>((r >> 24) & 0xff);
        value += static_cast<float>((sum - 510) * noise_scale);
      }
      row[u] = static_cast<uint8_t>(std::min(255.0f, std::max(0.0f, value + 0.5f)));
    }
  }
  texture_.evict(frame_, 40);
}

}  // namespace nadir::sim
