// bench_support_plane: the support plane (extension::find_support_plane) against PCL's RANSAC plane
// segmentation (SACSegmentation, SACMODEL_PERPENDICULAR_PLANE when gravity is known, else
// SACMODEL_PLANE) and PCL's organized multi-plane segmentation (OrganizedMultiPlaneSegmentation on
// the organized cloud with PCL's integral-image normals, as in PCL's tutorial; the normals are
// given to both and not timed; its plane is the largest one facing up within 15 degrees, or the
// largest when gravity is unknown), and the depth filter (signal::filter_depth) against OpenCV's bilateralFilter,
// in one process on the same frames: noisy synthetic VGA frames (exact table plane, clean depth)
// and the real mOSD frames (reference: a least-squares plane through the points labelled table).
//
// Per method: median ms per frame and the angle between the found normal and the reference
// (mean, max); for the filters, the RMS depth error against the clean depth. The last line is
// one JSON object.
//
//   bench_support_plane            12 synthetic seeds, 24 real frames, 5 repetitions
//   bench_support_plane --quick    a few frames (ctest)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>
#include <pcl/ModelCoefficients.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/features/integral_image_normal.h>
#include <pcl/segmentation/organized_multi_plane_segmentation.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "mereo/extension/normals.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/io/io.hpp"
#include "mereo/signal/depth_filter.hpp"
#include "mereo/synthetic/scene.hpp"
#include "bench_util.hpp"
#include "core/components.hpp"

namespace fs = std::filesystem;
using namespace mereo;
using bench::median;
using bench::now_ms;

namespace {

double angle_deg(Eigen::Vector3d a, Eigen::Vector3d b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180.0 / M_PI;
}

struct Input {
  std::string name;
  Cloud cloud;
  NormalMap normals;
  Eigen::Vector3d reference;             // the table's normal
  std::optional<Eigen::Vector3d> up;     // gravity, when known
  DepthImage noisy, clean;               // synthetic only
  pcl::PointCloud<pcl::PointXYZ>::Ptr pcl_cloud;
  pcl::PointCloud<pcl::PointXYZ>::Ptr organized;  // W x H, NaN where no depth
  pcl::PointCloud<pcl::Normal>::Ptr pcl_normals;   // PCL's integral-image normals
};

struct Stat {
  std::vector<double> ms, err, rms;
};

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--quick") quick = true;
  const int n_syn = quick ? 3 : 12, n_real = quick ? 2 : 24, repeats = quick ? 1 : 5;

  std::vector<Input> inputs;
  auto finish = [](Input& in) {
    in.normals = extension::estimate_normals(in.cloud);
    // the measured points (SACSegmentation) and the organized cloud, NaN where none (OMPS)
    const float nan = std::numeric_limits<float>::quiet_NaN();
    in.pcl_cloud.reset(new pcl::PointCloud<pcl::PointXYZ>);
    in.organized.reset(
        new pcl::PointCloud<pcl::PointXYZ>(in.cloud.cols(), in.cloud.rows(), pcl::PointXYZ(nan, nan, nan)));
    in.organized->is_dense = false;
    for (std::size_t i = 0; i < in.cloud.pixels(); ++i) {
      const float* p = in.cloud.data() + 3 * i;
      if (!std::isfinite(p[2])) continue;
      in.pcl_cloud->push_back(pcl::PointXYZ(p[0], p[1], p[2]));
      in.organized->points[i] = pcl::PointXYZ(p[0], p[1], p[2]);
    }
    pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
    ne.setNormalEstimationMethod(ne.AVERAGE_3D_GRADIENT);
    ne.setMaxDepthChangeFactor(0.02f);
    ne.setNormalSmoothingSize(10.0f);
    ne.setInputCloud(in.organized);
    in.pcl_normals.reset(new pcl::PointCloud<pcl::Normal>);
    ne.compute(*in.pcl_normals);
  };
  for (int s = 0; s < n_syn; ++s) {
    const auto sf = synthetic::render(std::uint64_t(300 + s));
    Input in;
    in.name = "synthetic:" + std::to_string(300 + s);
    in.cloud = extension::back_project(sf.frame);
    in.reference = sf.truth.camera_pose.linear().transpose() * Eigen::Vector3d::UnitZ();
    in.up = in.reference;
    in.noisy = sf.frame.depth;
    in.clean = sf.truth.depth;
    finish(in);
    inputs.push_back(std::move(in));
  }
  const fs::path real_dir = fs::path(MEREO_REAL_DATA) / "pcl-mosd";
  std::vector<fs::path> files;
  if (fs::is_directory(real_dir))
    for (const auto& e : fs::directory_iterator(real_dir))
      if (e.path().extension() == ".pcd") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (int i = 0; i < int(files.size()) && i < n_real; ++i) {
    const Frame f = io::read(files[i].string());
    Input in;
    in.name = files[i].filename().string();
    in.cloud = extension::back_project(f);
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    Eigen::Matrix3d ss = Eigen::Matrix3d::Zero();
    double n = 0;
    for (int v = 0; v < f.rows(); ++v)
      for (int u = 0; u < f.cols(); ++u)
        if (f.labels(v, u) >= 1 && f.labels(v, u) <= 9 && std::isfinite(in.cloud(v, u, 2))) {
          const Eigen::Vector3d x(in.cloud(v, u, 0), in.cloud(v, u, 1), in.cloud(v, u, 2));
          s += x, ss += x * x.transpose(), n += 1;
        }
    const Eigen::Vector3d c = s / n;
    in.reference = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(ss / n - c * c.transpose()).eigenvectors().col(0);
    finish(in);
    inputs.push_back(std::move(in));
  }

  Stat mereo_plane, pcl_plane, omps_plane, mereo_filter, cv_filter, mereo_cc, cv_cc;
  for (const Input& in : inputs) {
    for (int rep = 0; rep < repeats; ++rep) {
      extension::SupportPlaneOptions o;
      o.up = in.up;
      double t0 = now_ms();
      const auto plane = extension::find_support_plane(in.cloud, in.normals, o);
      mereo_plane.ms.push_back(now_ms() - t0);
      if (rep == 0) mereo_plane.err.push_back(angle_deg(plane.normal, in.reference));

      // the connected components of the plane's inlier mask: ours (on runs) and OpenCV's
      const cv::Mat on_plane(plane.inliers.rows(), plane.inliers.cols(), CV_8U, const_cast<std::uint8_t*>(plane.inliers.data()));
      t0 = now_ms();
      const Components runs = connected_components(on_plane);
      mereo_cc.ms.push_back(now_ms() - t0);
      cv::Mat labels, stats, centroids;
      t0 = now_ms();
      const int cv_count = cv::connectedComponentsWithStats(on_plane, labels, stats, centroids, 4, CV_32S);
      cv_cc.ms.push_back(now_ms() - t0);
      if (rep == 0 && runs.count() != cv_count - 1) {
        std::fprintf(stderr, "bench_support_plane: %s: %d components, OpenCV %d\n", in.name.c_str(), runs.count(), cv_count - 1);
        return 1;
      }

      pcl::SACSegmentation<pcl::PointXYZ> seg;
      seg.setOptimizeCoefficients(true);
      seg.setMethodType(pcl::SAC_RANSAC);
      seg.setDistanceThreshold(0.01);
      seg.setMaxIterations(200);
      if (in.up) {
        seg.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
        seg.setAxis(in.up->cast<float>());
        seg.setEpsAngle(15.0 * M_PI / 180.0);
      } else {
        seg.setModelType(pcl::SACMODEL_PLANE);
      }
      seg.setInputCloud(in.pcl_cloud);
      pcl::PointIndices inliers;
      pcl::ModelCoefficients coef;
      t0 = now_ms();
      seg.segment(inliers, coef);
      pcl_plane.ms.push_back(now_ms() - t0);
      if (rep == 0)
        pcl_plane.err.push_back(coef.values.size() == 4
                                    ? angle_deg(Eigen::Vector3d(coef.values[0], coef.values[1], coef.values[2]), in.reference)
                                    : 90.0);

      // PCL's organized multi-plane segmentation: its planes, and the support among them
      pcl::OrganizedMultiPlaneSegmentation<pcl::PointXYZ, pcl::Normal, pcl::Label> omps;
      omps.setMinInliers(unsigned(o.min_inliers));
      omps.setAngularThreshold(3.0 * M_PI / 180.0);
      omps.setDistanceThreshold(0.02);
      omps.setInputCloud(in.organized);
      omps.setInputNormals(in.pcl_normals);
      std::vector<pcl::ModelCoefficients> planes;
      std::vector<pcl::PointIndices> plane_inliers;
      t0 = now_ms();
      omps.segment(planes, plane_inliers);
      omps_plane.ms.push_back(now_ms() - t0);
      if (rep == 0) {
        std::size_t best = planes.size(), most = 0;
        for (std::size_t k = 0; k < planes.size(); ++k) {
          const Eigen::Vector3d n(planes[k].values[0], planes[k].values[1], planes[k].values[2]);
          if (in.up && std::abs(n.normalized().dot(*in.up)) < std::cos(15.0 * M_PI / 180.0)) continue;
          if (plane_inliers[k].indices.size() > most) most = plane_inliers[k].indices.size(), best = k;
        }
        omps_plane.err.push_back(best < planes.size() ? angle_deg(Eigen::Vector3d(planes[best].values[0],
                                                                                   planes[best].values[1],
                                                                                   planes[best].values[2]),
                                                                   in.reference)
                                                      : 90.0);
      }
      if (in.clean.empty()) continue;
      t0 = now_ms();
      const DepthImage ours = signal::filter_depth(in.noisy);
      mereo_filter.ms.push_back(now_ms() - t0);
      // OpenCV: depth with NaN replaced by 0 (bilateralFilter has no notion of missing data),
      // same window and a fixed range sigma (its kernel cannot grow with depth): 4 mm at 1 m.
      cv::Mat src(in.noisy.rows(), in.noisy.cols(), CV_32F, const_cast<float*>(in.noisy.data()));
      cv::Mat zero = src.clone();
      cv::patchNaNs(zero, 0.0);
      cv::Mat theirs;
      t0 = now_ms();
      cv::bilateralFilter(zero, theirs, 5, 0.004, 1.5);
      cv_filter.ms.push_back(now_ms() - t0);
      if (rep == 0) {
        double e0 = 0, e1 = 0;
        std::size_t n = 0;
        for (std::size_t i = 0; i < in.noisy.pixels(); ++i) {
          const float z = in.noisy.data()[i], c = in.clean.data()[i];
          if (!(z > 0) || !(c > 0)) continue;
          e0 += (ours.data()[i] - c) * (ours.data()[i] - c);
          const float t = theirs.ptr<float>()[i];
          e1 += (t - c) * (t - c);
          ++n;
        }
        mereo_filter.rms.push_back(1000 * std::sqrt(e0 / n));
        cv_filter.rms.push_back(1000 * std::sqrt(e1 / n));
      }
    }
  }
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? NAN : s / v.size();
  };
  auto maxv = [](const std::vector<double>& v) { return v.empty() ? NAN : *std::max_element(v.begin(), v.end()); };
  std::printf("bench_support_plane: %zu frames (%d synthetic, %zu real mOSD), %d repetitions\n\n", inputs.size(), n_syn,
              inputs.size() - n_syn, repeats);
  std::printf("%-34s %9s %14s %13s\n", "support plane", "ms", "mean err deg", "max err deg");
  std::printf("%-34s %9.2f %14.3f %13.3f\n", "mereo find_support_plane", median(mereo_plane.ms), mean(mereo_plane.err),
              maxv(mereo_plane.err));
  std::printf("%-34s %9.2f %14.3f %13.3f\n", "pcl SACSegmentation (RANSAC, LS)", median(pcl_plane.ms), mean(pcl_plane.err),
              maxv(pcl_plane.err));
  std::printf("%-34s %9.2f %14.3f %13.3f\n", "pcl OrganizedMultiPlaneSegmentation", median(omps_plane.ms),
              mean(omps_plane.err), maxv(omps_plane.err));
  std::printf("(speed-up over OrganizedMultiPlaneSegmentation: %.2fx)\n",
              median(omps_plane.ms) / median(mereo_plane.ms));
  std::printf("\n%-34s %9s\n", "components of the inliers (4-conn.)", "ms");
  std::printf("%-34s %9.2f\n", "mereo connected_components (runs)", median(mereo_cc.ms));
  std::printf("%-34s %9.2f\n", "opencv connectedComponentsWithStats", median(cv_cc.ms));
  std::printf("\n%-34s %9s %14s\n", "depth filter (synthetic)", "ms", "RMS err mm");
  std::printf("%-34s %9.2f %14.2f\n", "mereo filter_depth", median(mereo_filter.ms), mean(mereo_filter.rms));
  std::printf("%-34s %9.2f %14.2f\n", "opencv bilateralFilter", median(cv_filter.ms), mean(cv_filter.rms));
  std::printf("{\"bench\": \"support_plane\", \"quick\": %s, \"frames\": %zu, "
              "\"mereo_plane\": {\"median_ms\": %.3f, \"mean_error_deg\": %.4f, \"max_error_deg\": %.4f}, "
              "\"pcl_plane\": {\"median_ms\": %.3f, \"mean_error_deg\": %.4f, \"max_error_deg\": %.4f}, "
              "\"plane_speedup_vs_pcl\": %.3f, "
              "\"omps_plane\": {\"median_ms\": %.3f, \"mean_error_deg\": %.4f, \"max_error_deg\": %.4f}, "
              "\"plane_speedup_vs_omps\": %.3f, "
              "\"mereo_filter\": {\"median_ms\": %.3f, \"rms_mm\": %.3f}, \"opencv_bilateral\": {\"median_ms\": %.3f, \"rms_mm\": %.3f}, "
              "\"mereo_components_ms\": %.3f, \"opencv_components_ms\": %.3f}\n",
              quick ? "true" : "false", inputs.size(), median(mereo_plane.ms), mean(mereo_plane.err), maxv(mereo_plane.err),
              median(pcl_plane.ms), mean(pcl_plane.err), maxv(pcl_plane.err), median(pcl_plane.ms) / median(mereo_plane.ms),
              median(omps_plane.ms), mean(omps_plane.err), maxv(omps_plane.err), median(omps_plane.ms) / median(mereo_plane.ms),
              median(mereo_filter.ms), mean(mereo_filter.rms), median(cv_filter.ms), mean(cv_filter.rms), median(mereo_cc.ms),
              median(cv_cc.ms));
  return 0;
}
