#include "tools/export/sim_log.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/channels.h"
#include "common/config.h"
#include "nadir/config_t.hpp"

namespace nadir::exporter {
namespace {

std::string at(const std::string& path, uint64_t offset) {
  return path + ": byte " + std::to_string(offset) + ": ";
}

template <class T>
T decode(const LogEvent& e, const std::string& path) {
  T msg;
  if (msg.decode(e.data, 0, static_cast<int>(e.size)) < 0) {
    throw std::runtime_error(at(path, e.offset) + e.channel + " does not decode as its nadir type");
  }
  return msg;
}

template <class T>
size_t nearest(const std::vector<T>& v, int64_t utime) {
  auto it = std::lower_bound(v.begin(), v.end(), utime, [](const T& m, int64_t t) { return m.utime < t; });
  if (it == v.end()) return v.size() - 1;
  if (it == v.begin()) return 0;
  const auto before = it - 1;
  return static_cast<size_t>((utime - before->utime <= it->utime - utime ? before : it) - v.begin());
}

}  // namespace

std::unique_ptr<SimLog> SimLog::load(const std::string& path) {
  std::unique_ptr<SimLog> log(new SimLog(path));
  bool have_config = false;
  std::string other_configs;  // names of CONFIGs from other processes (a replay's output passes the sim's on)
  LogEvent e;
  while (log->reader_.next(&e)) {
    if (e.channel == channels::kConfig && !have_config) {
      const config_t config = decode<config_t>(e, path);
      if (config.name != "sim") {
        other_configs += (other_configs.empty() ? "'" : ", '") + config.name + "'";
        continue;
      }
      const Config root = Config::parse(config.yaml, path + " (CONFIG at byte " + std::to_string(e.offset) + ")");
      if (!root.has("camera")) {
        throw std::runtime_error(at(path, e.offset) + "CONFIG has no camera: section (a log of an older nadir_sim?)");
      }
      log->camera_ = CameraModel::from_config(root);
      have_config = true;
    } else if (e.channel == channels::kCameraImage) {
      // The header only; the pixels stay in the mapped file until exported.
      const image_t image = decode<image_t>(e, path);
      log->images_.push_back({image.utime, image.frame_counter, e.data, e.size, e.offset});
    } else if (e.channel == channels::kIns) {
      log->ins_.push_back(decode<ins_t>(e, path));
    } else if (e.channel == channels::kAltimeter) {
      log->altimeter_.push_back(decode<altimeter_t>(e, path));
    } else if (e.channel == channels::kGroundTruth) {
      const ground_truth_t truth = decode<ground_truth_t>(e, path);
      if (truth.kind == ground_truth_t::KIND_FRAME) log->frame_truth_.push_back(truth);
    }
  }
  std::string damage = log->reader_.corrupt_records() > 0 ? log->reader_.damage_report() : "";
  while (!damage.empty() && damage.back() == '\n') damage.pop_back();
  if (!damage.empty()) damage = " (" + damage + ")";
  if (!have_config) {
    const std::string others = other_configs.empty() ? "" : ", only from " + other_configs;
    throw std::runtime_error(path + ": no CONFIG record from nadir_sim" + others +
                             ": export needs a simulator log" + damage);
  }
  if (log->images_.empty()) throw std::runtime_error(path + ": no CAMERA_IMAGE in the log" + damage);
  if (log->ins_.size() < 2) throw std::runtime_error(path + ": fewer than two INS messages in the log" + damage);
  if (log->frame_truth_.empty()) throw std::runtime_error(path + ": no GROUND_TRUTH of frames in the log" + damage);
  auto by_time = [](const auto& a, const auto& b) { return a.utime < b.utime; };
  std::stable_sort(log->images_.begin(), log->images_.end(), by_time);
  std::stable_sort(log->ins_.begin(), log->ins_.end(), by_time);
  std::stable_sort(log->altimeter_.begin(), log->altimeter_.end(), by_time);
  std::stable_sort(log->frame_truth_.begin(), log->frame_truth_.end(), by_time);
  return log;
}

image_t SimLog::decode_image(const SimImageRef& ref) const {
  image_t image;
  if (image.decode(ref.data, 0, static_cast<int>(ref.size)) < 0) {
    throw std::runtime_error(at(path_, ref.offset) + "CAMERA_IMAGE does not decode");
  }
  if (image.pixel_format != image_t::PIXEL_MONO8 || image.stride < image.width ||
      static_cast<int64_t>(image.data.size()) < static_cast<int64_t>(image.stride) * image.height) {
    throw std::runtime_error(at(path_, ref.offset) + "CAMERA_IMAGE is not a complete MONO8 image");
  }
  if (image.width != camera_.width || image.height != camera_.height) {
    throw std::runtime_error(at(path_, ref.offset) + "CAMERA_IMAGE is " + std::to_string(image.width) + "x" +
                             std::to_string(image.height) + ", CONFIG's camera " + std::to_string(camera_.width) +
                             "x" + std::to_string(camera_.height));
  }
  return image;
}

const ground_truth_t& SimLog::truth_for_frame(int64_t image_utime) const {
  const ground_truth_t& truth = frame_truth_[nearest(frame_truth_, image_utime)];
  const double limit_us = 0.25e6 / camera_.rate_hz;  // the simulator's bound on the trigger jitter
  if (std::fabs(static_cast<double>(truth.utime - image_utime)) > limit_us) {
    throw std::runtime_error(path_ + ": no frame GROUND_TRUTH within " + std::to_string(limit_us * 1e-3) +
                             " ms of the image at utime " + std::to_string(image_utime));
  }
  return truth;
}

size_t SimLog::nearest_ins(int64_t utime) const { return nearest(ins_, utime); }

void SimLog::ins_position_at(int64_t utime, double* lat_deg, double* lon_deg, double* height_m) const {
  auto it = std::lower_bound(ins_.begin(), ins_.end(), utime, [](const ins_t& m, int64_t t) { return m.utime < t; });
  if (it == ins_.begin()) it = ins_.begin() + 1;
  if (it == ins_.end()) it = ins_.end() - 1;
  const ins_t& a = *(it - 1);
  const ins_t& b = *it;
  const double span = static_cast<double>(b.utime - a.utime);
  const double s = span > 0 ? std::clamp((utime - a.utime) / span, 0.0, 1.0) : 0.0;
  *lat_deg = a.latitude_deg + s * (b.latitude_deg - a.latitude_deg);
  *lon_deg = a.longitude_deg + s * (b.longitude_deg - a.longitude_deg);
  *height_m = a.height_m + s * (b.height_m - a.height_m);
}

double SimLog::yaw_rate_at(int64_t utime) const {
  const ins_t& m = ins_[nearest_ins(utime)];
  if (!m.has_rates) return 0.0;
  // Euler kinematics: yaw' = (q sin(roll) + r cos(roll)) / cos(pitch).
  return (m.angular_rate[1] * std::sin(m.roll) + m.angular_rate[2] * std::cos(m.roll)) / std::cos(m.pitch);
}

bool SimLog::range_near(int64_t utime, int64_t max_age_us, double* range_m) const {
  const altimeter_t* best = nullptr;
  auto it = std::lower_bound(altimeter_.begin(), altimeter_.end(), utime - max_age_us,
                             [](const altimeter_t& m, int64_t t) { return m.utime < t; });
  for (; it != altimeter_.end() && it->utime <= utime + max_age_us; ++it) {
    if (it->validity != altimeter_t::VALID_OK) continue;
    if (!best || std::llabs(it->utime - utime) < std::llabs(best->utime - utime)) best = &*it;
  }
  if (best) *range_m = best->range_m;
  return best != nullptr;
}

}  // namespace nadir::exporter
