// nadir_import_conventions: evidence for a photo flight's attitude conventions
// and focal length from the images themselves (independent of nadir's
// estimator). Consecutive photos are matched (ORB + RANSAC homography); the
// image displacement and rotation are compared with the GPS displacement, the
// heading change and the roll/pitch change. Used for the senseFly Seneca
// flight (docs/research/).
#include <CLI/CLI.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/camera_model.h"
#include "common/channels.h"
#include "common/config.h"
#include "common/geodetic.h"
#include "common/geometry.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "common/robust_stats.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "tools/import/photo_metadata.h"

namespace {

using nadir::deg_to_rad;
using nadir::rad_to_deg;

struct Pair {
  std::string a, b;
  double dpsi_deg = 0, image_rot_deg = 0;  // heading change; image content rotation (x toward y)
  Eigen::Vector2d u{0, 0};                 // image-b centre located in image a, minus image-a centre (px)
  Eigen::Vector2d d_ned{0, 0};             // GPS displacement (m)
  double psi_a = 0, psi_b = 0, roll_a = 0, roll_b = 0, pitch_a = 0, pitch_b = 0, h_a = 0, h_b = 0;
  int inliers = 0;
};

// The upper middle value (the figures in docs/research/2026-11-seneca.md were printed
// with it); NaN for no values, printed as such.
double median(const std::vector<double>& v) {
  return v.empty() ? NAN : nadir::median(v, nadir::EvenMedian::kUpper);
}

// ORB + ratio test + RANSAC homography a -> b. `u`: image b's centre located in image a, minus image a's
// centre (px); `rot_deg`: image content rotation (x toward y). False when fewer than 25 inliers.
bool match_pair(const cv::Mat& a, const cv::Mat& b, Eigen::Vector2d* u, double* rot_deg, int* inliers) {
  cv::Ptr<cv::ORB> orb = cv::ORB::create(4000);
  std::vector<cv::KeyPoint> ka, kb;
  cv::Mat da, db;
  orb->detectAndCompute(a, cv::noArray(), ka, da);
  orb->detectAndCompute(b, cv::noArray(), kb, db);
  if (da.empty() || db.empty()) return false;
  std::vector<std::vector<cv::DMatch>> knn;
  cv::BFMatcher(cv::NORM_HAMMING).knnMatch(da, db, knn, 2);
  std::vector<cv::Point2f> pa, pb;
  for (const auto& m : knn) {
    if (m.size() == 2 && m[0].distance < 0.8f * m[1].distance) {
      pa.push_back(ka[static_cast<size_t>(m[0].queryIdx)].pt);
      pb.push_back(kb[static_cast<size_t>(m[0].trainIdx)].pt);
    }
  }
  if (pa.size() < 20) return false;
  std::vector<unsigned char> mask;
  const cv::Mat h = cv::findHomography(pa, pb, cv::RANSAC, 3.0, mask, 5000, 0.999);
  if (h.empty()) return false;
  *inliers = cv::countNonZero(mask);
  if (*inliers < 25) return false;
  const double cx = (a.cols - 1) / 2.0, cy = (a.rows - 1) / 2.0;
  std::vector<cv::Point2f> c{cv::Point2f(static_cast<float>(cx), static_cast<float>(cy))}, in_a;
  cv::perspectiveTransform(c, in_a, h.inv());
  *u = Eigen::Vector2d(in_a[0].x - cx, in_a[0].y - cy);
  *rot_deg = rad_to_deg(std::atan2(h.at<double>(1, 0) - h.at<double>(0, 1), h.at<double>(0, 0) + h.at<double>(1, 1)));
  return true;
}

// Check of an imported log with nadir's own camera model (OUT.yaml): the ground point under image b's centre
// (ray through INS attitude + mount, plane at the altimeter's height below GROUND_TRUTH) projected into image a,
// against where the homography puts it.
int check_log(const std::string& log_path, const std::string& config_path) {
  const nadir::CameraModel cam = nadir::CameraModel::from_config(nadir::Config::load_file(config_path));
  struct Frame {
    cv::Mat image;
    Eigen::Matrix3d world_from_camera;
    Eigen::Vector3d position;
    double ground_down = 0;
  };
  std::vector<Frame> frames;
  nadir::LogReader reader(log_path);
  nadir::LogEvent e;
  std::string why;
  nadir::ins_t ins{};
  nadir::altimeter_t alt{};
  cv::Mat image;
  while (reader.next(&e)) {
    if (e.channel == nadir::channels::kIns) nadir::decode_message(e.data, e.size, &ins, &why);
    if (e.channel == nadir::channels::kAltimeter) nadir::decode_message(e.data, e.size, &alt, &why);
    if (e.channel == nadir::channels::kCameraImage) {
      nadir::image_t m;
      nadir::decode_message(e.data, e.size, &m, &why);
      image = cv::Mat(m.height, m.width, CV_8UC1, m.data.data(), static_cast<size_t>(m.stride)).clone();
    }
    if (e.channel == nadir::channels::kGroundTruth) {
      nadir::ground_truth_t g;
      nadir::decode_message(e.data, e.size, &g, &why);
      Frame f;
      f.image = image;
      f.world_from_camera = nadir::rotation_from_rpy(ins.roll, ins.pitch, ins.yaw) * cam.body_from_camera;
      f.position = Eigen::Vector3d(g.position_ned[0], g.position_ned[1], g.position_ned[2]);
      f.ground_down = f.position.z() + alt.range_m;
      frames.push_back(f);
    }
  }
  std::vector<double> err_px, rel;
  for (size_t i = 0; i + 1 < frames.size(); ++i) {
    const Frame& a = frames[i];
    const Frame& b = frames[i + 1];
    Eigen::Vector2d u;
    double rot = 0;
    int inliers = 0;
    if (!match_pair(a.image, b.image, &u, &rot, &inliers)) continue;
    // ray through b's principal point
    const Eigen::Vector3d ray = b.world_from_camera * Eigen::Vector3d(0, 0, 1);
    const double ground = 0.5 * (a.ground_down + b.ground_down);  // flat ground between the two
    const Eigen::Vector3d g = b.position + ray * (ground - b.position.z()) / ray.z();
    const Eigen::Vector3d in_a = a.world_from_camera.transpose() * (g - a.position);
    const std::vector<cv::Point2f> px = cam.distort({cv::Point2d(in_a.x() / in_a.z(), in_a.y() / in_a.z())});
    const Eigen::Vector2d predicted(px[0].x - cam.cx, px[0].y - cam.cy);
    err_px.push_back((predicted - u).norm());
    rel.push_back(err_px.back() / u.norm());
  }
  std::printf("%s with %s: %zu of %zu consecutive pairs matched; image b's centre predicted in image a from INS + "
              "mount + GROUND_TRUTH + ALTIMETER vs the homography: median error %.1f px, %.1f %% of the displacement\n",
              log_path.c_str(), config_path.c_str(), err_px.size(), frames.size() - 1, median(err_px), 100 * median(rel));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir;
  double scale = 0.5;
  double max_dpsi = 20.0;
  CLI::App app{"Matches consecutive photos of a senseFly flight and prints the evidence for heading / roll / pitch "
               "signs, which image axis is forward, and the focal length (docs/research/2026-11-seneca.md).",
               "nadir_import_conventions"};
  std::string log_path, config_path;
  app.add_option("--photos", dir, "photo folder (senseFly XMP)");
  app.add_option("--log", log_path, "instead: check an imported log (with --config OUT.yaml) against its images");
  app.add_option("--config", config_path, "the import's OUT.yaml (with --log)");
  app.add_option("--scale", scale, "image scale for matching")->capture_default_str();
  app.add_option("--max-dpsi", max_dpsi, "pairs with a smaller heading change are used for the fits (deg)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    if (!log_path.empty()) return check_log(log_path, config_path);
    if (dir.empty()) throw std::invalid_argument("give --photos DIR or --log FILE --config FILE");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_import_conventions: error: %s\n", e.what());
    return 2;
  }

  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<nadir::import::PhotoMetadata> meta;
  std::vector<cv::Mat> images;
  for (const auto& f : files) {
    cv::Mat g = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    if (g.empty()) continue;
    nadir::import::PhotoMetadata m = nadir::import::read_photo_metadata(f.string());
    if (!m.has_sensefly_attitude || !m.has_sensefly_position || !m.has_sensefly_height) continue;
    cv::resize(g, g, cv::Size(), scale, scale, cv::INTER_AREA);
    meta.push_back(m);
    images.push_back(g);
  }
  if (meta.empty()) {
    std::fprintf(stderr, "nadir_import_conventions: error: %s: no image with senseFly position, attitude and height\n",
                 dir.c_str());
    return 2;
  }
  // Every photo's north/east along the path from the first (common/geodetic.h).
  std::vector<Eigen::Vector2d> photo_ne;
  nadir::GeodeticTrack track({meta.front().sf_lat_deg, meta.front().sf_lon_deg, 0.0});
  for (const auto& m : meta) photo_ne.push_back(track.ned({m.sf_lat_deg, m.sf_lon_deg, 0.0}).head<2>());
  std::vector<Pair> pairs;
  for (size_t i = 0; i + 1 < images.size(); ++i) {
    if (images[i].size() != images[i + 1].size()) continue;
    Pair p;
    if (!match_pair(images[i], images[i + 1], &p.u, &p.image_rot_deg, &p.inliers)) continue;
    const auto& ma = meta[i];
    const auto& mb = meta[i + 1];
    p.a = std::filesystem::path(ma.path).filename().string();
    p.b = std::filesystem::path(mb.path).filename().string();
    p.d_ned = photo_ne[i + 1] - photo_ne[i];
    p.psi_a = ma.sf_heading_deg, p.psi_b = mb.sf_heading_deg;
    p.roll_a = ma.sf_roll_deg, p.roll_b = mb.sf_roll_deg;
    p.pitch_a = ma.sf_pitch_deg, p.pitch_b = mb.sf_pitch_deg;
    p.h_a = ma.sf_height_m, p.h_b = mb.sf_height_m;
    p.dpsi_deg = rad_to_deg(nadir::wrap_angle(deg_to_rad(p.psi_b - p.psi_a)));
    pairs.push_back(p);
  }
  std::printf("pairs matched: %zu of %zu consecutive (>= 25 homography inliers)\n", pairs.size(), images.size() - 1);
  std::printf("%-13s %-13s %6s %8s %8s %8s %8s %7s %7s %7s %7s %6s\n", "a", "b", "inl", "dpsi", "img_rot", "u_col",
              "u_row", "dN", "dE", "droll", "dpitch", "h");
  for (const Pair& p : pairs) {
    std::printf("%-13s %-13s %6d %8.2f %8.2f %8.1f %8.1f %7.1f %7.1f %7.2f %7.2f %6.1f\n", p.a.c_str(), p.b.c_str(),
                p.inliers, p.dpsi_deg, p.image_rot_deg, p.u.x(), p.u.y(), p.d_ned.x(), p.d_ned.y(),
                p.roll_b - p.roll_a, p.pitch_b - p.pitch_a, p.h_a);
  }
  // A. heading direction: image rotation vs heading change (expect -1 for clockwise-from-north).
  {
    double sxy = 0, sxx = 0;
    for (const Pair& p : pairs) sxy += p.dpsi_deg * p.image_rot_deg, sxx += p.dpsi_deg * p.dpsi_deg;
    std::vector<double> sum;
    for (const Pair& p : pairs) sum.push_back(p.image_rot_deg + p.dpsi_deg);
    std::printf("\nA. image rotation = %.3f x heading change (least squares through 0, %zu pairs); "
                "median(img_rot + dpsi) = %.2f deg\n", sxy / sxx, pairs.size(), median(sum));
  }
  // B. which image axis is forward, and f: u*h = A * d_body (body-a frame, heading clockwise from north).
  std::vector<const Pair*> straight;
  for (const Pair& p : pairs) {
    if (std::abs(p.dpsi_deg) < max_dpsi) straight.push_back(&p);
  }
  auto body = [](const Pair& p, double psi_deg) {
    const double c = std::cos(deg_to_rad(psi_deg)), s = std::sin(deg_to_rad(psi_deg));
    return Eigen::Vector2d(c * p.d_ned.x() + s * p.d_ned.y(), -s * p.d_ned.x() + c * p.d_ned.y());
  };
  {
    Eigen::MatrixXd x(static_cast<long>(straight.size()), 2), y(static_cast<long>(straight.size()), 2);
    for (size_t k = 0; k < straight.size(); ++k) {
      const Pair& p = *straight[k];
      x.row(static_cast<long>(k)) = body(p, p.psi_a).transpose();
      y.row(static_cast<long>(k)) = (p.u * p.h_a).transpose();
    }
    const Eigen::Matrix2d a = (x.transpose() * x).ldlt().solve(x.transpose() * y).transpose();
    std::printf("\nB. [u_col u_row]*h = A [forward right] over %zu pairs with |dpsi| < %.0f deg (px at scale %.2f):\n"
                "   A = [%8.1f %8.1f; %8.1f %8.1f]\n", straight.size(), max_dpsi, scale, a(0, 0), a(0, 1), a(1, 0),
                a(1, 1));
  }
  // C. roll / pitch signs and f with the axis from B: image top = forward, columns = right.
  // Ground point at the image centre: P + h * R(psi) [sp*tan(pitch), -sr*tan(roll)] (small angles).
  std::printf("\nC. top = forward, columns = right; tilt hypotheses (sr: roll sign, sp: pitch sign), f fitted:\n");
  for (int sr : {0, 1, -1}) {
    for (int sp : {0, 1, -1}) {
      if ((sr == 0) != (sp == 0)) continue;
      auto predicted_body = [&](const Pair& p) {
        auto offset = [&](double roll, double pitch, double psi, double h) {
          const Eigen::Vector2d fr(sp * std::tan(deg_to_rad(pitch)) * h, -sr * std::tan(deg_to_rad(roll)) * h);
          const double c = std::cos(deg_to_rad(psi)), s = std::sin(deg_to_rad(psi));
          return Eigen::Vector2d(c * fr.x() - s * fr.y(), s * fr.x() + c * fr.y());  // NE
        };
        const Eigen::Vector2d g = p.d_ned + offset(p.roll_b, p.pitch_b, p.psi_b, p.h_b) - offset(p.roll_a, p.pitch_a, p.psi_a, p.h_a);
        const double c = std::cos(deg_to_rad(p.psi_a)), s = std::sin(deg_to_rad(p.psi_a));
        return Eigen::Vector2d(c * g.x() + s * g.y(), -s * g.x() + c * g.y());
      };
      double num = 0, den = 0;
      for (const Pair* p : straight) {
        const Eigen::Vector2d b = predicted_body(*p);
        const Eigen::Vector2d img_dir(b.y(), -b.x());  // (col, row) per metre over h
        num += img_dir.dot(p->u * p->h_a);
        den += img_dir.squaredNorm();
      }
      const double f = num / den;
      std::vector<double> err, rel;
      for (const Pair* p : straight) {
        const Eigen::Vector2d b = predicted_body(*p);
        const Eigen::Vector2d pred = f / p->h_a * Eigen::Vector2d(b.y(), -b.x());
        err.push_back((pred - p->u).norm());
        rel.push_back((pred - p->u).norm() / p->u.norm());
      }
      std::printf("   sr %+d sp %+d: f = %7.1f px, median |residual| %6.1f px, median relative %5.1f %%\n", sr, sp, f,
                  median(err), 100 * median(rel));
    }
  }
  // D. heading bias: direction of the image displacement (as body axes) vs the GPS track in the body frame.
  {
    std::vector<double> bias;
    for (const Pair* p : straight) {
      const Eigen::Vector2d b = body(*p, p->psi_a);
      const Eigen::Vector2d measured_fr(-p->u.y(), p->u.x());
      bias.push_back(rad_to_deg(std::atan2(measured_fr.y(), measured_fr.x()) - std::atan2(b.y(), b.x())));
      bias.back() = rad_to_deg(nadir::wrap_angle(deg_to_rad(bias.back())));
    }
    std::printf("\nD. image track direction minus GPS track direction in the body frame: median %.2f deg\n", median(bias));
  }
  // E. free fit: u*h = a * img(d_body) + b * img(roll term) + c * img(pitch term) (linear least squares);
  // b/a and c/a near +1 confirm sr = sp = +1, near -1 the opposite; a = f.
  {
    Eigen::MatrixXd x(2 * static_cast<long>(straight.size()), 4);
    Eigen::VectorXd y(2 * static_cast<long>(straight.size()));
    auto rot = [](double psi_deg, const Eigen::Vector2d& v) {  // body-level (forward, right) -> NE
      const double c = std::cos(deg_to_rad(psi_deg)), s = std::sin(deg_to_rad(psi_deg));
      return Eigen::Vector2d(c * v.x() - s * v.y(), s * v.x() + c * v.y());
    };
    for (size_t k = 0; k < straight.size(); ++k) {
      const Pair& p = *straight[k];
      const Eigen::Vector2d d = rot(-p.psi_a, p.d_ned);
      const Eigen::Vector2d rterm = rot(-p.psi_a, rot(p.psi_b, {0, -p.h_b * std::tan(deg_to_rad(p.roll_b))}) -
                                                     rot(p.psi_a, {0, -p.h_a * std::tan(deg_to_rad(p.roll_a))}));
      const Eigen::Vector2d pterm = rot(-p.psi_a, rot(p.psi_b, {p.h_b * std::tan(deg_to_rad(p.pitch_b)), 0}) -
                                                     rot(p.psi_a, {p.h_a * std::tan(deg_to_rad(p.pitch_a)), 0}));
      const long r = 2 * static_cast<long>(k);
      // image (col, row) = (right, -forward) / h
      // 4th column: the displacement turned 90 deg clockwise in the body (a yaw offset's first-order term)
      x.row(r) << d.y(), rterm.y(), pterm.y(), d.x();
      x.row(r + 1) << -d.x(), -rterm.x(), -pterm.x(), d.y();
      y(r) = p.u.x() * p.h_a;
      y(r + 1) = p.u.y() * p.h_a;
    }
    const Eigen::Vector4d c = (x.transpose() * x).ldlt().solve(x.transpose() * y);
    const Eigen::VectorXd res = y - x * c;
    // standard errors of the coefficients (residual variance x (X^T X)^-1), and of the ratios (first order)
    const double sigma2 = res.squaredNorm() / static_cast<double>(y.size() - 4);
    const Eigen::Matrix4d cov = sigma2 * (x.transpose() * x).inverse();
    std::printf("\nE. standard errors: f %.1f px, roll coefficient / f %.2f, pitch coefficient / f %.2f, turn %.2f deg\n",
                std::sqrt(cov(0, 0)), std::sqrt(cov(1, 1)) / c(0), std::sqrt(cov(2, 2)) / c(0),
                rad_to_deg(std::sqrt(cov(3, 3)) / c(0)));
    std::vector<double> rel;
    for (size_t k = 0; k < straight.size(); ++k) {
      rel.push_back(Eigen::Vector2d(res(2 * static_cast<long>(k)), res(2 * static_cast<long>(k) + 1)).norm() /
                    (straight[k]->u * straight[k]->h_a).norm());
    }
    std::printf("\nE. free linear fit over %zu pairs: f = %.1f px (scale %.2f), roll coefficient / f = %.2f, "
                "pitch coefficient / f = %.2f, image track turned by %.2f deg clockwise from the GPS track in the body frame, "
                "median relative residual %.1f %%\n",
                straight.size(), c(0), scale, c(1) / c(0), c(2) / c(0), rad_to_deg(std::atan2(c(3), c(0))), 100 * median(rel));
  }
  return 0;
}
