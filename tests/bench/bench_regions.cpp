// bench_regions: the objects standing on the support as regions (features::object_regions: the
// free-form regions and unknown objects of the tabletop graph) against PCL's Euclidean cluster
// extraction (EuclideanClusterExtraction with a k-d tree, the tabletop tutorial's segmentation)
// on the same points above the same support plane, in one process: rendered frames of both
// depth models with free-form distractors (exact object ids per pixel) and the real mOSD frames
// (their per-point object labels).
//
// An object (at least 800 pixels above the support) is segmented when one region holds it with an
// intersection over union of at least 0.5; merged when its best region holds at least half of it
// but also enough of others to fall below 0.5. Per method and frame set: objects segmented and
// merged, median ms per frame, and the speed ratio; and mereo's regions without the silhouette
// rule (depth jumps only), which shows what it adds. The last line is one JSON object.
//
//   bench_regions           24 rendered frames (12 per depth model), 24 mOSD frames, 3 repetitions
//   bench_regions --quick   a few frames (ctest)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include "bench_util.hpp"
#include "mereo/extension/normals.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/features/regions.hpp"
#include "mereo/io/io.hpp"
#include "mereo/matching/interpret.hpp"
#include "mereo/synthetic/scene.hpp"

namespace fs = std::filesystem;
using namespace mereo;

namespace {

// the tabletop graph's values: the regions' and the clusters' least size and distance at 1 m
const matching::InterpretOptions kGraph;
const int kMinPixels = kGraph.min_unknown_pixels;
const double kDepthJump = kGraph.depth_jump;

struct Input {
  std::string set, name;
  Cloud cloud;
  NormalMap normals;
  extension::SupportPlane plane;
  std::vector<int> truth;  // object id per pixel, 0 = none
};

struct Score {
  int objects = 0, segmented = 0, merged = 0;
  std::vector<double> ms;
};

/// Objects segmented and merged by `regions` (pixel lists) against the ids in `in.truth` (their
/// pixels inside the support's region of interest).
void score(const Input& in, const std::vector<std::vector<int>>& regions, Score& s) {
  std::map<int, int> size;  // object id -> pixels in the roi
  for (std::size_t i = 0; i < in.truth.size(); ++i)
    if (in.truth[i] > 0 && in.plane.roi.data()[i] && valid_point(in.cloud.data() + 3 * i)) ++size[in.truth[i]];
  for (const auto& [id, n] : size) {
    if (n < kMinPixels) continue;
    ++s.objects;
    double best_iou = 0, best_share = 0;
    for (const auto& r : regions) {
      int inter = 0;
      for (int i : r) inter += in.truth[std::size_t(i)] == id;
      if (!inter) continue;
      best_iou = std::max(best_iou, double(inter) / double(int(r.size()) + n - inter));
      best_share = std::max(best_share, double(inter) / n);
    }
    if (best_iou >= 0.5) ++s.segmented;
    else if (best_share >= 0.5) ++s.merged;
  }
}

/// PCL: the roi's valid points clustered at kDepthJump times their median depth.
std::vector<std::vector<int>> pcl_clusters(const Input& in) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr pts(new pcl::PointCloud<pcl::PointXYZ>);
  std::vector<int> pixel;
  std::vector<float> z;
  for (std::size_t i = 0; i < in.cloud.pixels(); ++i) {
    const float* p = in.cloud.data() + 3 * i;
    if (in.plane.roi.data()[i] && valid_point(p)) pts->push_back({p[0], p[1], p[2]}), pixel.push_back(int(i)), z.push_back(p[2]);
  }
  std::vector<std::vector<int>> out;
  if (pts->empty()) return out;
  std::nth_element(z.begin(), z.begin() + std::ptrdiff_t(z.size() / 2), z.end());
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(pts);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(kDepthJump * z[z.size() / 2]);
  ec.setMinClusterSize(kMinPixels);
  ec.setMaxClusterSize(int(pts->size()));
  ec.setSearchMethod(tree);
  ec.setInputCloud(pts);
  std::vector<pcl::PointIndices> clusters;
  ec.extract(clusters);
  for (const auto& c : clusters) {
    out.emplace_back();
    for (int k : c.indices) out.back().push_back(pixel[std::size_t(k)]);
  }
  return out;
}

bool prepare(Input& in) {
  in.normals = extension::estimate_normals(in.cloud);
  try {
    in.plane = extension::find_support_plane(in.cloud, in.normals);
  } catch (const std::exception& e) {
    std::printf("  %s: no support plane (%s)\n", in.name.c_str(), e.what());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--quick") quick = true;
  const int n_syn = quick ? 2 : 12, n_real = quick ? 2 : 24, repeats = quick ? 1 : 3;

  std::vector<Input> inputs;
  for (const char* model : {"kinect", "stereo"})
    for (int s = 0; s < n_syn; ++s) {
      synthetic::SceneOptions so;
      so.depth_model = std::string(model) == "kinect" ? synthetic::DepthModel::Kinect : synthetic::DepthModel::Stereo;
      so.freeform_distractors = true;
      const auto sf = synthetic::render(std::uint64_t(8000 + s), so);
      Input in;
      in.set = std::string("rendered ") + model;
      in.name = "synthetic:" + std::to_string(8000 + s);
      in.cloud = extension::back_project(sf.frame);
      in.truth.assign(sf.truth.objects.data(), sf.truth.objects.data() + sf.truth.objects.pixels());
      for (int& id : in.truth) {
        const auto* o = id > 0 ? sf.truth.object(std::uint32_t(id)) : nullptr;
        if (o && (o->model == "table" || o->model == "floor" || o->model == "wall")) id = 0;
      }
      if (prepare(in)) inputs.push_back(std::move(in));
    }
  const fs::path real_dir = fs::path(MEREO_REAL_DATA) / "pcl-mosd";
  std::vector<fs::path> files;
  if (fs::is_directory(real_dir)) {
    for (const auto& e : fs::directory_iterator(real_dir))
      if (e.path().extension() == ".pcd") files.push_back(e.path());
  } else {
    std::printf("(no %s: the real frames are skipped)\n", real_dir.string().c_str());
  }
  std::sort(files.begin(), files.end());
  for (int i = 0; i < int(files.size()) && i < n_real; ++i) {
    const Frame f = io::read(files[std::size_t(i)].string());
    Input in;
    in.set = "mOSD (real)";
    in.name = files[std::size_t(i)].filename().string();
    in.cloud = extension::back_project(f);
    in.truth.resize(f.labels.pixels());
    for (std::size_t k = 0; k < f.labels.pixels(); ++k)
      in.truth[k] = f.labels.data()[k] >= 20 ? int(f.labels.data()[k] / 10) : 0;  // object id = label / 10
    if (prepare(in)) inputs.push_back(std::move(in));
  }

  std::map<std::string, Score> ours, pcl, jumps;
  std::vector<std::string> sets;
  for (const Input& in : inputs) {
    if (std::find(sets.begin(), sets.end(), in.set) == sets.end()) sets.push_back(in.set);
    std::vector<std::vector<int>> a, b;
    std::vector<double> ta, tb;
    for (int r = 0; r < repeats; ++r) {
      double t0 = bench::now_ms();
      a = features::object_regions(in.cloud, in.plane.roi, &in.normals, kDepthJump, kGraph.max_grazing_deg, kMinPixels);
      ta.push_back(bench::now_ms() - t0);
      t0 = bench::now_ms();
      b = pcl_clusters(in);
      tb.push_back(bench::now_ms() - t0);
    }
    score(in, a, ours[in.set]), ours[in.set].ms.push_back(bench::median(ta));
    score(in, features::object_regions(in.cloud, in.plane.roi, nullptr, kDepthJump, kGraph.max_grazing_deg, kMinPixels), jumps[in.set]);
    score(in, b, pcl[in.set]), pcl[in.set].ms.push_back(bench::median(tb));
  }

  std::printf("%-18s %-28s %8s %10s %7s %9s\n", "frames", "method", "objects", "segmented", "merged", "ms/frame");
  std::string json = "{";
  for (const auto& set : sets) {
    const Score& o = ours[set];
    const Score& p = pcl[set];
    std::printf("%-18s %-28s %8d %10d %7d %9.2f\n", set.c_str(), "mereo object_regions", o.objects, o.segmented, o.merged,
                bench::median(o.ms));
    std::printf("%-18s %-28s %8d %10d %7d\n", set.c_str(), "  (without silhouettes)", jumps[set].objects,
                jumps[set].segmented, jumps[set].merged);
    std::printf("%-18s %-28s %8d %10d %7d %9.2f\n", set.c_str(), "PCL EuclideanClusterExtraction", p.objects,
                p.segmented, p.merged, bench::median(p.ms));
    const double ratio = bench::median(p.ms) / bench::median(o.ms);
    std::printf("%-18s speed: mereo %.1fx PCL's\n", "", ratio);
    if (json.size() > 1) json += ", ";
    json += "\"" + set + "\": {\"objects\": " + std::to_string(o.objects) + ", \"segmented\": " +
            std::to_string(o.segmented) + ", \"merged\": " + std::to_string(o.merged) +
            ", \"segmented_without_silhouettes\": " + std::to_string(jumps[set].segmented) +
            ", \"pcl_segmented\": " + std::to_string(p.segmented) + ", \"pcl_merged\": " + std::to_string(p.merged) +
            ", \"ms\": " + bench::json_number(bench::median(o.ms), 2) +
            ", \"pcl_ms\": " + bench::json_number(bench::median(p.ms), 2) + ", \"speedup\": " + bench::json_number(ratio, 2) +
            "}";
  }
  std::printf("%s}\n", json.c_str());
  return 0;
}
