// bench_normals: mereo's per-pixel normals against PCL's IntegralImageNormalEstimation (all four
// modes) and OpenCV's rgbd::RgbdNormals (FALS, LINEMOD, SRI), in one process, on the same VGA
// frames, in four sets: rendered scenes with exact normals in both depth models (Kinect-like and
// active stereo), the real mOSD frames (Kinect), and real RealSense-like frames (nv-6dof-graspnet
// and PoseCNN's, with many depth edges and dropouts).
//
// Per method: median ms per frame, mean and median angular error against the exact normals
// (synthetic frames; the angle between lines, i.e. acos|n . n_true|, so that orientation
// conventions do not count), and the share of valid input points that got a normal.
// The inputs are converted to each library's type outside the timed region; only the normal
// computation is timed. Methods are interleaved per frame and repetition so that machine load
// affects them alike. The last line is one JSON object.
//
// Per set it prints mereo_fast against OpenCV's FALS: median ms, speed-up, and on the rendered
// sets the mean error on the pixels both cover (issue 22: at least 1.5x faster on every set, at
// a lower error; the real sets have no true normals, so only their speed is compared).
//
//   bench_normals            the full run (20 seeds per rendered set, 24 mOSD and 10 RealSense-like
//                            frames, 5 repetitions)
//   bench_normals --quick    a few frames (ctest)
//   bench_normals --set S    only set S (kinect, stereo, mosd, realsense; repeatable)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/rgbd.hpp>
#include <pcl/features/integral_image_normal.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "mereo/extension/normals.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/io/io.hpp"
#include "mereo/synthetic/scene.hpp"
#include "bench_util.hpp"

namespace fs = std::filesystem;
using namespace mereo;
using bench::median;
using bench::now_ms;

namespace {

struct Input {
  std::string name;
  std::string set;  // kinect, stereo (rendered), mosd, realsense (real)
  bool synthetic = false;
  Cloud cloud;
  NormalMap truth;  // empty for real frames
  Intrinsics K;
  // library inputs, prepared once per frame (outside the timed region)
  pcl::PointCloud<pcl::PointXYZ>::Ptr pcl_cloud;
  cv::Mat cv_points;     // CV_32FC3 view of `cloud`
  cv::Mat cv_depth_mm;   // CV_32FC1, millimetres (LINEMOD's depth threshold is 50 units)
};

struct Method {
  std::string name;
  std::string settings;
  std::function<NormalMap(const Input&)> run;  // returns normals; timing covers only the call
  std::vector<double> ms, ms_synthetic, ms_real;
  std::map<std::string, std::vector<double>> ms_set;
  std::vector<float> errors;
  std::size_t valid_in = 0, valid_out = 0;
};



NormalMap from_mat(const cv::Mat& m) {
  NormalMap n(m.rows, m.cols, kNaN);
  for (int v = 0; v < m.rows; ++v) std::memcpy(n.ptr(v, 0), m.ptr<float>(v), sizeof(float) * 3 * m.cols);
  return n;
}

Input prepare(std::string name, std::string set, bool synthetic, Cloud cloud, NormalMap truth, Intrinsics K) {
  Input in;
  in.name = std::move(name);
  in.set = std::move(set);
  in.synthetic = synthetic;
  in.cloud = std::move(cloud);
  in.truth = std::move(truth);
  in.K = K;
  const int H = in.cloud.rows(), W = in.cloud.cols();
  in.pcl_cloud.reset(new pcl::PointCloud<pcl::PointXYZ>(W, H));
  in.pcl_cloud->is_dense = false;
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      const float* p = in.cloud.ptr(v, u);
      auto& q = in.pcl_cloud->at(u, v);
      q.x = p[0], q.y = p[1], q.z = p[2];
    }
  in.cv_points = cv::Mat(H, W, CV_32FC3, in.cloud.data());
  in.cv_depth_mm = cv::Mat(H, W, CV_32FC1);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) in.cv_depth_mm.at<float>(v, u) = in.cloud(v, u, 2) * 1000.f;
  return in;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::vector<std::string> only;  // --set NAME (repeatable): those sets alone
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "--set" && i + 1 < argc) only.push_back(argv[++i]);
    else {
      std::fprintf(stderr, "bench_normals: unknown argument %s (--quick, --set kinect|stereo|mosd|realsense)\n", a.c_str());
      return 2;
    }
  }
  const auto wanted = [&](const std::string& set) {
    return only.empty() || std::find(only.begin(), only.end(), set) != only.end();
  };
  const int n_synthetic = quick ? 3 : 20;
  const int n_real = quick ? 2 : 24;
  const int n_realsense = quick ? 1 : 5;  // per folder
  const int repeats = quick ? 2 : 5;
  const int fast_window = 5, cov_window = 9;
  const float depth_change = 0.02f;

  // ---- frames ----
  std::vector<Input> inputs;
  for (const auto model : {synthetic::DepthModel::Kinect, synthetic::DepthModel::Stereo}) {
    synthetic::SceneOptions so;
    so.depth_model = model;
    const std::string set = model == synthetic::DepthModel::Kinect ? "kinect" : "stereo";
    for (int s = 0; s < n_synthetic && wanted(set); ++s) {
      auto sf = synthetic::render(std::uint64_t(100 + s), so);
      inputs.push_back(prepare("synthetic:" + std::to_string(100 + s) + " (" + set + ")", set, true,
                               extension::back_project(sf.frame), sf.truth.normals, sf.frame.intrinsics));
    }
  }
  const fs::path real_dir = fs::path(MEREO_REAL_DATA) / "pcl-mosd";
  if (!fs::is_directory(real_dir))
    std::printf("real frames skipped (%s not found: they sit beside a clone of the repository)\n",
                real_dir.parent_path().c_str());
  if (fs::is_directory(real_dir)) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(real_dir))
      if (e.path().extension() == ".pcd") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (int i = 0; i < int(files.size()) && i < n_real && wanted("mosd"); ++i) {
      Frame f = io::read(files[i].string());
      inputs.push_back(prepare(files[i].filename().string(), "mosd", false, extension::back_project(f),
                               NormalMap(), f.intrinsics));
    }
    // RealSense-like: nv-6dof-graspnet (its camera_params.json) and PoseCNN's frames (its camera,
    // SOURCE.md; depth in 0.1 mm)
    io::ReadOptions posecnn;
    posecnn.intrinsics = Intrinsics{1066.778, 1067.487, 312.9869, 241.3109};
    posecnn.depth_scale = 10000.0;
    const fs::path real = real_dir.parent_path();
    for (const auto& [folder, ro] : {std::make_pair(std::string("nv-6dof-graspnet"), io::ReadOptions{}),
                                     std::make_pair(std::string("posecnn"), posecnn)}) {
      const io::Sequence seq = io::open({(real / folder).string()}, ro);
      for (std::size_t i = 0; i < seq.size() && int(i) < n_realsense && wanted("realsense"); ++i) {
        Frame f = seq.load(i);
        inputs.push_back(prepare(folder + " " + f.id, "realsense", false, extension::back_project(f), NormalMap(),
                                 f.intrinsics));
      }
    }
  }
  const std::vector<std::string> sets = {"kinect", "stereo", "mosd", "realsense"};
  for (const auto& set : only)
    if (std::find(sets.begin(), sets.end(), set) == sets.end()) {
      std::fprintf(stderr, "bench_normals: unknown set %s (kinect, stereo, mosd or realsense)\n", set.c_str());
      return 2;
    }
  if (inputs.empty()) {
    std::printf("bench_normals: no frames (the real sets need ../shared/data/real beside the clone)\n");
    return 0;
  }

  // ---- methods ----
  std::vector<Method> methods;
  auto add_mereo = [&](std::string name, extension::NormalOptions o, std::string settings) {
    methods.push_back({name, settings, [o](const Input& in) { return extension::estimate_normals(in.cloud, o); }});
  };
  {
    extension::NormalOptions o;
    o.method = extension::NormalMethod::Fast;
    o.window = fast_window;
    o.depth_change_factor = depth_change;
    add_mereo("mereo_fast", o, "window 5, depth_change_factor 0.02");
    o.method = extension::NormalMethod::Covariance;
    o.window = cov_window;
    o.adaptive_window = false;
    add_mereo("mereo_covariance", o, "window 9 (fixed), depth_change_factor 0.02");
    o.adaptive_window = true;
    add_mereo("mereo_covariance_adaptive", o,
              "window 9 at 1 m, side 9 m / z in [3, 19], depth_change_factor 0.02");
  }
  const std::pair<const char*, pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal>::NormalEstimationMethod>
      pcl_modes[] = {{"pcl_COVARIANCE_MATRIX", pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal>::COVARIANCE_MATRIX},
                     {"pcl_AVERAGE_3D_GRADIENT", pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal>::AVERAGE_3D_GRADIENT},
                     {"pcl_AVERAGE_DEPTH_CHANGE", pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal>::AVERAGE_DEPTH_CHANGE},
                     {"pcl_SIMPLE_3D_GRADIENT", pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal>::SIMPLE_3D_GRADIENT}};
  for (const auto& [name, mode] : pcl_modes) {
    methods.push_back({name,
                       "normal smoothing size 9 (its window: 9x9), max depth change factor 0.02 "
                       "(PCL tutorial values: 10 and 0.02; 9 = mereo's window), "
                       "no depth-dependent smoothing, border policy ignore",
                       [mode = mode, depth_change, cov_window](const Input& in) {
                         pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
                         ne.setNormalEstimationMethod(mode);
                         ne.setMaxDepthChangeFactor(depth_change);
                         ne.setNormalSmoothingSize(float(cov_window));
                         ne.setDepthDependentSmoothing(false);
                         ne.setInputCloud(in.pcl_cloud);
                         pcl::PointCloud<pcl::Normal> out;
                         ne.compute(out);
                         NormalMap n(int(out.height), int(out.width), kNaN);
                         for (std::size_t i = 0; i < out.size(); ++i) {
                           n.data()[3 * i] = out[i].normal_x;
                           n.data()[3 * i + 1] = out[i].normal_y;
                           n.data()[3 * i + 2] = out[i].normal_z;
                         }
                         return n;
                       }});
  }
  // OpenCV: one cached RgbdNormals per method and intrinsics (construction and initialize()
  // precompute per-pixel tables; not timed)
  struct CvCache {
    Intrinsics K;
    cv::Ptr<cv::rgbd::RgbdNormals> n;
  };
  const std::pair<const char*, int> cv_modes[] = {
      {"opencv_FALS", cv::rgbd::RgbdNormals::RGBD_NORMALS_METHOD_FALS},
      {"opencv_LINEMOD", cv::rgbd::RgbdNormals::RGBD_NORMALS_METHOD_LINEMOD},
      {"opencv_SRI", cv::rgbd::RgbdNormals::RGBD_NORMALS_METHOD_SRI}};
  auto caches = std::make_shared<std::vector<CvCache>>(3);
  for (int m = 0; m < 3; ++m) {
    const int mode = cv_modes[m].second;
    const bool linemod = mode == cv::rgbd::RgbdNormals::RGBD_NORMALS_METHOD_LINEMOD;
    methods.push_back(
        {cv_modes[m].first,
         linemod ? "depth in mm as CV_32F (its 50-unit depth threshold = 50 mm), fixed 11x11 "
                   "sampling (window_size unused), CV_32F"
                 : "window_size 5 (default), CV_32F, 3D points input",
         [m, mode, linemod, caches](const Input& in) {
           // the cache is filled before timing (see the warm-up below)
           auto& c = (*caches)[m];
           cv::Mat normals;
           (*c.n)(linemod ? in.cv_depth_mm : in.cv_points, normals);
           return from_mat(normals);
         }});
  }
  auto ensure_cv = [&](const Input& in) {
    for (int m = 0; m < 3; ++m) {
      auto& c = (*caches)[m];
      if (c.n && c.K == in.K) continue;
      cv::Mat K = (cv::Mat_<double>(3, 3) << in.K.fx, 0, in.K.cx, 0, in.K.fy, in.K.cy, 0, 0, 1);
      c.K = in.K;
      c.n = cv::rgbd::RgbdNormals::create(in.cloud.rows(), in.cloud.cols(), CV_32F, K, 5, cv_modes[m].second);
      c.n->initialize();
    }
  };

  std::map<std::string, int> per_set;
  for (const auto& in : inputs) ++per_set[in.set];
  std::printf("bench_normals: %zu frames (rendered VGA: %d Kinect-like, %d active stereo; real: %d mOSD, %d "
              "RealSense-like), %d repetitions, %d threads for mereo (oneTBB) and OpenCV, PCL single-threaded\n",
              inputs.size(), per_set["kinect"], per_set["stereo"], per_set["mosd"], per_set["realsense"], repeats,
              cv::getNumThreads());

  // Mean errors of two methods over the pixels where both give a normal (a method that leaves
  // the hard pixels near edges empty is not rewarded for it).
  struct Pair {
    std::string a, b;
    double sum_a = 0, sum_b = 0;
    std::size_t n = 0;
  };
  std::vector<Pair> pairs = {{"mereo_fast", "opencv_FALS"}, {"mereo_fast", "opencv_LINEMOD"},
                             {"mereo_fast", "opencv_SRI"}, {"mereo_covariance", "pcl_COVARIANCE_MATRIX"},
                             {"mereo_covariance_adaptive", "pcl_COVARIANCE_MATRIX"}};
  auto method_index = [&](const std::string& name) {
    for (std::size_t i = 0; i < methods.size(); ++i)
      if (methods[i].name == name) return i;
    return std::size_t(0);
  };
  std::map<std::string, Pair> fast_fals_error;  // per rendered set: mereo_fast against FALS
  auto error_at = [](const NormalMap& n, const NormalMap& truth, std::size_t i) {
    const float* q = n.data() + 3 * i;
    const float* t = truth.data() + 3 * i;
    if (!(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2])) || !std::isfinite(t[0])) return -1.0;
    const double len = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2]);
    const double c = std::abs(double(q[0]) * t[0] + double(q[1]) * t[1] + double(q[2]) * t[2]) / len;
    return std::acos(std::min(1.0, c)) * 180.0 / M_PI;
  };

  // ---- run ----
  for (const Input& in : inputs) {
    ensure_cv(in);
    std::vector<NormalMap> results(methods.size());
    for (int rep = 0; rep < repeats + 1; ++rep) {
      for (std::size_t m = 0; m < methods.size(); ++m) {
        const double t0 = now_ms();
        NormalMap n = methods[m].run(in);
        const double t = now_ms() - t0;
        if (rep == 0) {  // warm-up (first touch of buffers, lazy init); keep its result
          results[m] = n;
          continue;
        }
        methods[m].ms.push_back(t);
        (in.synthetic ? methods[m].ms_synthetic : methods[m].ms_real).push_back(t);
        methods[m].ms_set[in.set].push_back(t);
      }
    }
    if (in.synthetic) {
      auto& fs_err = fast_fals_error[in.set];
      const NormalMap& na = results[method_index("mereo_fast")];
      const NormalMap& nb = results[method_index("opencv_FALS")];
      for (std::size_t i = 0; i < in.cloud.pixels(); ++i) {
        const double ea = error_at(na, in.truth, i), eb = error_at(nb, in.truth, i);
        if (ea < 0 || eb < 0) continue;
        fs_err.sum_a += ea, fs_err.sum_b += eb, ++fs_err.n;
      }
    }
    if (in.synthetic)
      for (auto& pr : pairs) {
        const NormalMap& na = results[method_index(pr.a)];
        const NormalMap& nb = results[method_index(pr.b)];
        for (std::size_t i = 0; i < in.cloud.pixels(); ++i) {
          const double ea = error_at(na, in.truth, i), eb = error_at(nb, in.truth, i);
          if (ea < 0 || eb < 0) continue;
          pr.sum_a += ea, pr.sum_b += eb, ++pr.n;
        }
      }
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const NormalMap& n = results[m];
      const int H = in.cloud.rows(), W = in.cloud.cols();
      for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) {
          const float* p = in.cloud.ptr(v, u);
          if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && p[2] > 0.f)) continue;
          ++methods[m].valid_in;
          const float* q = n.ptr(v, u);
          if (!(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]))) continue;
          ++methods[m].valid_out;
          if (!in.synthetic) continue;
          const float* t = in.truth.ptr(v, u);
          if (!std::isfinite(t[0])) continue;
          const double len = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2]);
          const double c = std::abs(double(q[0]) * t[0] + double(q[1]) * t[1] + double(q[2]) * t[2]) / len;
          methods[m].errors.push_back(float(std::acos(std::min(1.0, c)) * 180.0 / M_PI));
        }
    }
  }

  // ---- report ----
  struct Row {
    double ms, ms_syn, ms_real, mean, med, valid;
  };
  std::vector<Row> rows;
  std::printf("\n%-28s %9s %9s %9s %10s %10s %8s\n", "method", "ms", "ms_syn", "ms_real", "mean_deg",
              "median_deg", "valid");
  for (auto& m : methods) {
    double mean = 0;
    for (float e : m.errors) mean += e;
    mean = m.errors.empty() ? NAN : mean / m.errors.size();
    double med = NAN;
    if (!m.errors.empty()) {
      std::nth_element(m.errors.begin(), m.errors.begin() + m.errors.size() / 2, m.errors.end());
      med = m.errors[m.errors.size() / 2];
    }
    const Row r{median(m.ms), median(m.ms_synthetic), median(m.ms_real), mean, med,
                m.valid_in ? double(m.valid_out) / m.valid_in : 0.0};
    rows.push_back(r);
    std::printf("%-28s %9.2f %9.2f %9.2f %10.2f %10.2f %8.3f\n", m.name.c_str(), r.ms, r.ms_syn,
                r.ms_real, r.mean, r.med, r.valid);
  }
  std::printf("\nsettings:\n");
  for (auto& m : methods) std::printf("  %-28s %s\n", m.name.c_str(), m.settings.c_str());

  auto idx = [&](const std::string& name) {
    for (std::size_t i = 0; i < methods.size(); ++i)
      if (methods[i].name == name) return i;
    return std::size_t(0);
  };
  std::size_t cv_fastest = idx("opencv_FALS");
  for (const char* n : {"opencv_LINEMOD", "opencv_SRI"})
    if (rows[idx(n)].ms < rows[cv_fastest].ms) cv_fastest = idx(n);
  const Row& fast = rows[idx("mereo_fast")];
  const Row& cov = rows[idx("mereo_covariance")];
  const Row& cova = rows[idx("mereo_covariance_adaptive")];
  const Row& pcl_cov = rows[idx("pcl_COVARIANCE_MATRIX")];
  auto common = [&](const std::string& a, const std::string& b) {
    for (const auto& pr : pairs)
      if (pr.a == a && pr.b == b) return std::make_pair(pr.sum_a / double(pr.n), pr.sum_b / double(pr.n));
    return std::make_pair(double(NAN), double(NAN));
  };
  std::printf("\nmean error on the pixels where both give a normal (synthetic frames):\n");
  for (const auto& pr : pairs)
    std::printf("  %-26s %6.2f deg vs %-22s %6.2f deg (%zu pixels)\n", pr.a.c_str(), pr.sum_a / pr.n,
                pr.b.c_str(), pr.sum_b / pr.n, pr.n);
  const auto fast_common = common("mereo_fast", methods[cv_fastest].name);
  const auto cov_common = common("mereo_covariance", "pcl_COVARIANCE_MATRIX");
  const auto cova_common = common("mereo_covariance_adaptive", "pcl_COVARIANCE_MATRIX");
  const double fast_speedup = rows[cv_fastest].ms / fast.ms;
  const double cov_speedup = pcl_cov.ms / cov.ms;
  const double cova_speedup = pcl_cov.ms / cova.ms;
  // the error condition is checked on the common pixels; the coverage (valid share) is printed
  const bool fast_ok = fast_speedup >= 1.5 && fast_common.first <= fast_common.second;
  const bool cov_ok = cov_speedup >= 3.0 && cov_common.first <= cov_common.second;
  const bool cova_ok = cova_speedup >= 3.0 && cova_common.first <= cova_common.second;
  std::printf("\nmereo_fast vs %s (OpenCV's fastest here): %.2fx faster, mean error %.2f vs %.2f deg on common "
              "pixels (%.2f vs %.2f on each one's own), coverage %.3f vs %.3f -> %s\n",
              methods[cv_fastest].name.c_str(), fast_speedup, fast_common.first, fast_common.second, fast.mean,
              rows[cv_fastest].mean, fast.valid, rows[cv_fastest].valid,
              fast_ok ? "target met (>= 1.5x, error <=)" : "TARGET MISSED");
  std::printf("mereo_covariance vs pcl_COVARIANCE_MATRIX: %.2fx faster, mean error %.2f vs %.2f deg on common "
              "pixels (%.2f vs %.2f on each one's own), coverage %.3f vs %.3f -> %s\n",
              cov_speedup, cov_common.first, cov_common.second, cov.mean, pcl_cov.mean, cov.valid, pcl_cov.valid,
              cov_ok ? "target met (>= 3x, error <=)" : "TARGET MISSED");
  std::printf("mereo_covariance_adaptive vs pcl_COVARIANCE_MATRIX: %.2fx faster, mean error %.2f vs %.2f deg on "
              "common pixels -> %s\n",
              cova_speedup, cova_common.first, cova_common.second, cova_ok ? "target met" : "target missed");

  // per set: mereo_fast against FALS (the issue-22 target: at least 1.5x faster on every set, at a
  // lower error where the truth is known)
  const Method& fast_m = methods[idx("mereo_fast")];
  const Method& fals_m = methods[idx("opencv_FALS")];
  std::printf("\nmereo_fast vs opencv_FALS per frame set:\n  %-10s %6s %9s %9s %8s %14s  %s\n", "set", "frames",
              "fast_ms", "FALS_ms", "speedup", "error_deg", "target (>= 1.5x, error <=)");
  std::string sets_json;
  bool every_set_ok = true;
  for (const std::string& set : sets) {
    if (!fast_m.ms_set.count(set) || !fals_m.ms_set.count(set)) continue;  // (a set without frames)
    const double a = median(fast_m.ms_set.at(set)), b = median(fals_m.ms_set.at(set));
    const auto e = fast_fals_error.find(set);
    const bool truth = e != fast_fals_error.end() && e->second.n > 0;
    const double ea = truth ? e->second.sum_a / double(e->second.n) : NAN;
    const double eb = truth ? e->second.sum_b / double(e->second.n) : NAN;
    const bool ok = b / a >= 1.5 && (!truth || ea <= eb);
    every_set_ok = every_set_ok && ok;
    char err[64];
    if (truth) std::snprintf(err, sizeof err, "%.2f vs %.2f", ea, eb);
    else std::snprintf(err, sizeof err, "(no truth)");
    std::printf("  %-10s %6d %9.2f %9.2f %7.2fx %14s  %s\n", set.c_str(), per_set[set], a, b, b / a, err,
                ok ? "met" : "MISSED");
    char buf2[256];
    std::snprintf(buf2, sizeof buf2, "%s\"%s\": {\"frames\": %d, \"fast_ms\": %.3f, \"fals_ms\": %.3f, \"speedup\": %.3f, "
                  "\"fast_error_deg\": %s, \"fals_error_deg\": %s, \"target_met\": %s}",
                  sets_json.empty() ? "" : ", ", set.c_str(), per_set[set], a, b, b / a,
                  bench::json_number(ea).c_str(), bench::json_number(eb).c_str(), ok ? "true" : "false");
    sets_json += buf2;
  }

  std::string json = "{\"bench\": \"normals\", \"quick\": " + std::string(quick ? "true" : "false") +
                     ", \"frames_synthetic\": " + std::to_string(per_set["kinect"] + per_set["stereo"]) +
                     ", \"frames_real\": " + std::to_string(per_set["mosd"] + per_set["realsense"]) +
                     ", \"repeats\": " + std::to_string(repeats) + ", \"methods\": {";
  char buf[512];
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const Row& r = rows[i];
    std::snprintf(buf, sizeof buf,
                  "%s\"%s\": {\"median_ms\": %.3f, \"median_ms_synthetic\": %s, \"median_ms_real\": %s, "
                  "\"mean_error_deg\": %s, \"median_error_deg\": %s, \"valid_share\": %.4f}",
                  i ? ", " : "", methods[i].name.c_str(), r.ms, bench::json_number(r.ms_syn).c_str(),
                  bench::json_number(r.ms_real).c_str(), bench::json_number(r.mean).c_str(),
                  bench::json_number(r.med).c_str(), r.valid);
    json += buf;
  }
  std::snprintf(buf, sizeof buf,
                "}, \"opencv_fastest\": \"%s\", \"fast_speedup_vs_opencv_fastest\": %.3f, "
                "\"covariance_speedup_vs_pcl_covariance\": %.3f, \"covariance_adaptive_speedup_vs_pcl_covariance\": %.3f, "
                "\"fast_common_mean_error_deg\": [%s, %s], \"covariance_common_mean_error_deg\": [%s, %s], "
                "\"fast_target_met\": %s, \"covariance_target_met\": %s, \"fast_target_met_on_every_set\": %s, ",
                methods[cv_fastest].name.c_str(), fast_speedup, cov_speedup, cova_speedup,
                bench::json_number(fast_common.first).c_str(), bench::json_number(fast_common.second).c_str(),
                bench::json_number(cov_common.first).c_str(), bench::json_number(cov_common.second).c_str(),
                fast_ok ? "true" : "false", cov_ok ? "true" : "false", every_set_ok ? "true" : "false");
  json += buf;
  json += "\"sets\": {" + sets_json + "}}";
  std::printf("%s\n", json.c_str());
  return 0;
}
