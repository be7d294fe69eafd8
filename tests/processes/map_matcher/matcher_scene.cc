#include "tests/processes/map_matcher/matcher_scene.h"

#include <vector>

#include "common/geometry.h"
#include "processes/sim/renderer.h"
#include "tools/map/geotiff_writer.h"
#include "tools/map/simulated_map.h"

namespace nadir::test {

image_t mono8_frame(std::vector<uint8_t> pixels, int width, int height, int64_t utime) {
  image_t image{};
  image.utime = utime;
  image.width = width;
  image.height = height;
  image.stride = width;
  image.pixel_format = image_t::PIXEL_MONO8;
  image.size = static_cast<int32_t>(pixels.size());
  image.data = std::move(pixels);
  return image;
}

image_t rendered_frame(const sim::SimCamera& camera, const sim::Terrain& terrain, double north, double east,
                       double height_agl, const Eigen::Vector3d& rpy, uint64_t noise_key, int64_t utime) {
  sim::Renderer renderer(camera, terrain, sim::RendererOptions{});
  std::vector<uint8_t> pixels;
  renderer.render({north, east, -(terrain.height(north, east) + height_agl)},
                  rotation_from_rpy(rpy.x(), rpy.y(), rpy.z()) * camera.body_from_camera, noise_key, &pixels);
  return mono8_frame(std::move(pixels), camera.width, camera.height, utime);
}

pose_t prior_pose(double north, double east, const Eigen::Vector3d& rpy, double height_agl, double sigma,
                  int64_t utime) {
  pose_t p{};
  p.utime = utime;
  p.position_ned[0] = north;
  p.position_ned[1] = east;
  p.roll = rpy.x();
  p.pitch = rpy.y();
  p.yaw = rpy.z();
  p.height_agl_m = height_agl;
  p.position_covariance[0][0] = p.position_covariance[1][1] = sigma * sigma;
  p.position_covariance[2][2] = 1.0;
  return p;
}

void write_simulated_map(const std::string& dir, const sim::FlightProfile& profile, uint64_t seed, double margin_m) {
  map::SimulatedMapOptions options;
  options.margin_m = margin_m;
  const map::SimulatedMap m = map::simulate_map(profile, seed, options);
  map::write_geotiff_byte(dir + "/orthophoto.tif", m.grid, m.orthophoto);
  map::write_geotiff_float(dir + "/dem.tif", m.grid, m.dem, -9999.0);
}

}  // namespace nadir::test
