// bench_legs: the legs under a room's level patches (features::find_legs: a grid of cells on the
// floor under each table top and seat) against PCL's Euclidean cluster extraction (a k-d tree) of
// the same points under each patch, its clusters kept by the same rules (narrow, spanning most of
// the height, reaching up to the patch; not find_legs' last one, a leg rising on past the patch
// alone, which costs it a few legs), on rendered rooms of both depth models with exact part
// labels: the room graph's steps (depth filter, points, normals, the floor, patches) run once per
// frame, then both methods on the same patches and points.
//
// A leg (a table's or a chair's, or an office chair's column) counts when at least 100 of its
// pixels show and its top or seat is one of the patches: found when a leg segment's pixels are
// mostly its own. A segment on anything else is false. Per method and set: legs found, false
// ones, median ms per frame and the speed ratio. The last line is one JSON object.
//
//   bench_legs           20 rendered rooms per depth model (seeds 9100-9119, the tuning rooms)
//   bench_legs --quick   4 rooms per depth model (ctest)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include "bench_util.hpp"
#include "mereo/extension/normals.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/features/legs.hpp"
#include "mereo/features/patches.hpp"
#include "mereo/shapes/cylinder.hpp"
#include "mereo/shapes/patch.hpp"
#include "mereo/signal/depth_filter.hpp"
#include "mereo/synthetic/scene.hpp"

using namespace mereo;

namespace {

struct Score {
  int legs = 0, found = 0, false_legs = 0;
  std::vector<double> ms;
};

/// PCL: per level patch, the points under it (the rules of find_legs) clustered at the grid's cell
/// size, each cluster kept as a leg by find_legs' rules; the pixels of each kept cluster.
std::vector<std::vector<int>> pcl_legs(const Cloud& cloud, const std::vector<Segment>& patches,
                                       const Eigen::Vector3d& up, double d, const features::LegOptions& o) {
  std::vector<std::vector<int>> out;
  std::vector<std::uint8_t> taken(cloud.pixels(), 0);
  for (const auto* top : features::leg_tops(patches, up, d, o)) {
    const double h = up.dot(top->point) + d;
    const Eigen::Vector3d eu = (top->u_axis - up * up.dot(top->u_axis)).normalized(), ev = up.cross(eu);
    const double hu = 0.5 * top->size_u + o.margin, hv = 0.5 * top->size_v + o.margin;
    pcl::PointCloud<pcl::PointXYZ>::Ptr pts(new pcl::PointCloud<pcl::PointXYZ>);
    std::vector<int> pixel;
    std::vector<float> height;
    for (std::size_t i = 0; i < cloud.pixels(); i += std::size_t(o.step)) {
      const float* q = cloud.data() + 3 * i;
      if (taken[i] || !valid_point(q)) continue;
      const Eigen::Vector3d x(q[0], q[1], q[2]);
      const double y = up.dot(x) + d;
      if (y < o.floor_clear || y > h - o.top_clear) continue;
      if (std::abs(eu.dot(x - top->point)) > hu || std::abs(ev.dot(x - top->point)) > hv) continue;
      // clustered across up only, as the grid is: the height scaled away
      const Eigen::Vector3d flat = x - up * up.dot(x);
      pts->push_back({float(flat.x()), float(flat.y()), float(flat.z())});
      pixel.push_back(int(i)), height.push_back(float(y));
    }
    if (pts->empty()) continue;
    pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
    tree->setInputCloud(pts);
    pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
    ec.setClusterTolerance(o.cell);
    ec.setMinClusterSize(o.min_points);
    ec.setMaxClusterSize(int(pts->size()));
    ec.setSearchMethod(tree);
    ec.setInputCloud(pts);
    std::vector<pcl::PointIndices> clusters;
    ec.extract(clusters);
    for (const auto& c : clusters) {
      float lo = INFINITY, hi = -INFINITY;
      Eigen::Vector2d mn(INFINITY, INFINITY), mx(-INFINITY, -INFINITY);
      for (int k : c.indices) {
        const Eigen::Vector3d p(pts->points[std::size_t(k)].x, pts->points[std::size_t(k)].y, pts->points[std::size_t(k)].z);
        const Eigen::Vector2d ab(eu.dot(p), ev.dot(p));
        mn = mn.cwiseMin(ab), mx = mx.cwiseMax(ab);
        lo = std::min(lo, height[std::size_t(k)]), hi = std::max(hi, height[std::size_t(k)]);
      }
      const double width = (mx - mn).maxCoeff() + o.cell;
      if (!features::leg_shaped(width, lo, hi, h, o)) continue;
      out.emplace_back();
      for (int k : c.indices) out.back().push_back(pixel[std::size_t(k)]), taken[std::size_t(pixel[std::size_t(k)])] = 1;
    }
  }
  return out;
}

/// Legs found and false among `legs` (pixel lists) against the frame's part labels.
void score(const synthetic::SyntheticFrame& sf, const std::set<std::uint32_t>& tops_found,
           const std::vector<std::vector<int>>& legs, Score& s) {
  std::map<std::uint32_t, std::uint32_t> top_of;  // a leg's label -> its top's or seat's
  std::set<std::uint32_t> leg_labels;
  for (const auto& o : sf.truth.objects_truth) {
    const auto* top = o.part("top") ? o.part("top") : o.part("seat");
    if (!top) continue;
    for (const auto& p : o.parts)
      if ((p.role.rfind("leg", 0) == 0 || p.role == "column")) {
        leg_labels.insert(p.label);
        if (p.visible_pixels >= 100) top_of[p.label] = top->label;
      }
  }
  std::set<std::uint32_t> hit;
  for (const auto& l : legs) {
    std::map<std::uint32_t, int> count;
    for (int i : l) ++count[sf.truth.parts.data()[std::size_t(i)]];
    const auto best = std::max_element(count.begin(), count.end(), [](auto& a, auto& b) { return a.second < b.second; });
    if (best == count.end() || !leg_labels.count(best->first)) ++s.false_legs;
    else hit.insert(best->first);
  }
  for (const auto& [leg, top] : top_of)
    if (tops_found.count(top)) ++s.legs, s.found += hit.count(leg) > 0;
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  const int rooms = quick ? 4 : 20;
  const features::LegOptions lo;
  // the room graph's steps (graphs/room.yaml)
  signal::DepthFilterOptions fo;
  fo.radius = 2;
  extension::NormalOptions no;
  no.window = 15;
  extension::SupportPlaneOptions so;
  so.prefer = extension::SupportPlaneOptions::Prefer::Lowest, so.min_share = 0.1, so.max_height = 2.5, so.candidates = 6;
  std::map<std::string, Score> mine, pcl;
  std::vector<std::string> order;
  for (const std::string model : {"kinect", "stereo"}) {
    order.push_back(model);
    synthetic::SceneOptions opt;
    opt.room = true;
    opt.depth_model = model == "kinect" ? synthetic::DepthModel::Kinect : synthetic::DepthModel::Stereo;
    for (int seed = 9100; seed < 9100 + rooms; ++seed) {
      const auto sf = synthetic::render(std::uint64_t(seed), opt);
      const Frame f = signal::filter_depth(sf.frame, fo);
      const Cloud cloud = extension::back_project(f);
      const NormalMap normals = extension::estimate_normals(cloud, no);
      extension::SupportPlane floor;
      try {
        floor = extension::find_support_plane(cloud, normals, so);
      } catch (const std::exception&) {
        continue;
      }
      const auto patches = features::planar_patches(cloud, normals, {}, &floor.normal, &f.color);
      std::set<std::uint32_t> tops_found;  // the parts the patches lie on
      for (const auto& s : patches) {
        std::map<std::uint32_t, int> count;
        for (int i : s.pixels) ++count[sf.truth.parts.data()[std::size_t(i)]];
        const auto best = std::max_element(count.begin(), count.end(), [](auto& a, auto& b) { return a.second < b.second; });
        if (best != count.end()) tops_found.insert(best->first);
      }
      double t0 = bench::now_ms();
      const auto legs = features::find_legs(cloud, patches, floor.normal, floor.d, lo);
      mine[model].ms.push_back(bench::now_ms() - t0);
      std::vector<std::vector<int>> ours;
      for (const auto& l : legs) ours.push_back(l.pixels);
      score(sf, tops_found, ours, mine[model]);
      t0 = bench::now_ms();
      const auto theirs = pcl_legs(cloud, patches, floor.normal, floor.d, lo);
      pcl[model].ms.push_back(bench::now_ms() - t0);
      score(sf, tops_found, theirs, pcl[model]);
    }
  }
  std::printf("bench_legs: %d rendered rooms per depth model (seeds 9100-%d)\n\n", rooms, 9099 + rooms);
  std::printf("%-8s %-32s %6s %7s %7s %9s\n", "set", "method", "legs", "found", "false", "ms/frame");
  std::string json = "{";
  for (const auto& set : order) {
    const Score &a = mine[set], &b = pcl[set];
    std::printf("%-8s %-32s %6d %7d %7d %9.2f\n", set.c_str(), "mereo find_legs", a.legs, a.found, a.false_legs,
                bench::median(a.ms));
    std::printf("%-8s %-32s %6d %7d %7d %9.2f\n", set.c_str(), "PCL EuclideanClusterExtraction", b.legs, b.found,
                b.false_legs, bench::median(b.ms));
    const double ratio = bench::median(b.ms) / bench::median(a.ms);
    std::printf("%-8s speed: mereo %.1fx PCL's\n", "", ratio);
    if (json.size() > 1) json += ", ";
    json += "\"" + set + "\": {\"legs\": " + std::to_string(a.legs) + ", \"found\": " + std::to_string(a.found) +
            ", \"false\": " + std::to_string(a.false_legs) + ", \"pcl_found\": " + std::to_string(b.found) +
            ", \"pcl_false\": " + std::to_string(b.false_legs) + ", \"ms\": " + bench::json_number(bench::median(a.ms), 2) +
            ", \"pcl_ms\": " + bench::json_number(bench::median(b.ms), 2) + ", \"speedup\": " + bench::json_number(ratio, 2) + "}";
  }
  std::printf("%s}\n", json.c_str());
  return 0;
}
