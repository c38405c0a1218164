// bench_primitives: primitive detection (features::detect_primitives) against CGAL's Efficient
// RANSAC (planes, cylinders, spheres, tori) and PCL's SACSegmentationFromNormals
// (SACMODEL_NORMAL_PLANE, then SACMODEL_CYLINDER, extracted repeatedly), in one process on the
// same points and normals, in two settings:
//  - the whole frame, every class: mereo and CGAL on all valid pixels;
//  - the region above the table (the pipeline's setting, find_support_plane's ROI): mereo and
//    PCL on the same pixels (PCL's cylinder segmentation visits every point per iteration: on a
//    whole VGA frame it takes minutes).
// Figures, per method:
//  - noisy synthetic VGA frames (seeds 900-919): body recall (cylindrical bodies with >= 500
//    visible pixels), median radius and axis errors, the radius bias (mean signed error) by
//    distance from the camera, handle recall (mug handles with >= 150
//    visible pixels within 1.2 m), false cylinders and tori per frame (eval_primitives.hpp);
//  - the 24 mOSD frames: per frame, the upright cylindrical objects (reference circle fits to
//    the labelled points) and whether each method gives one of them a cylinder whose inliers
//    are at least 80% that object's;
//  - pcl/table_scene_mug_stereo_textured.pcd: the mug body's radius against a circle fitted to
//    the wall points above the table.
// Times are per frame (median), mereo's over its whole detection (planes, cylinders, spheres,
// tori and the handle search), given the camera's focal length as the pipeline's node gives it.
// The last line is one JSON object.
//
//   bench_primitives            20 synthetic frames, 24 mOSD frames, the real mug (~10 min)
//   bench_primitives --quick    1 synthetic frame, 1 mOSD frame, the mug (ctest)
//   options: --synthetic N, --real N (frame counts), --mereo-only (skip the anchors; tuning)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "anchors/anchors.hpp"
#include "bench_util.hpp"
#include "eval_primitives.hpp"
#include "mereo/extension/normals.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/features/primitives.hpp"
#include "mereo/io/io.hpp"
#include "mereo/synthetic/scene.hpp"

namespace fs = std::filesystem;
using namespace mereo;
using bench::median;
using bench::now_ms;

namespace {

struct Input {
  std::string name;
  Cloud cloud;
  NormalMap normals;
  ColorImage color;
  std::vector<int> index;                  // finite pixel of each anchor point
  std::vector<Eigen::Vector3f> points, point_normals;
  extension::Mask roi;                      // above the table
  std::vector<int> roi_index;               // the same for the points of the ROI
  std::vector<Eigen::Vector3f> roi_points, roi_normals;
  std::optional<synthetic::GroundTruth> truth;
  LabelImage labels;                        // mOSD
  Eigen::Vector3d up = Eigen::Vector3d::Zero();  // the table's normal (real frames)
  double focal = 0;  // the camera's, as the pipeline's node gives it (DetectOptions::focal_px)
};

Input prepare(std::string name, Cloud cloud, ColorImage color, double focal) {
  Input in;
  in.name = std::move(name);
  in.focal = focal;
  in.cloud = std::move(cloud);
  in.color = std::move(color);
  in.normals = extension::estimate_normals(in.cloud);
  const auto plane = extension::find_support_plane(in.cloud, in.normals);
  in.up = plane.normal;
  in.roi = plane.roi;
  for (std::size_t i = 0; i < in.cloud.pixels(); ++i) {
    const float* p = in.cloud.data() + 3 * i;
    const float* n = in.normals.data() + 3 * i;
    if (!std::isfinite(p[2]) || !std::isfinite(n[0])) continue;
    in.index.push_back(int(i));
    in.points.emplace_back(p[0], p[1], p[2]);
    in.point_normals.emplace_back(n[0], n[1], n[2]);
    if (!in.roi.data()[i]) continue;
    in.roi_index.push_back(int(i));
    in.roi_points.emplace_back(p[0], p[1], p[2]);
    in.roi_normals.emplace_back(n[0], n[1], n[2]);
  }
  return in;
}

/// An anchor's shapes as segments over the frame's pixels.
std::vector<Segment> to_segments(const std::vector<bench::AnchorShape>& shapes, const std::vector<int>& index) {
  std::vector<Segment> out;
  for (const auto& a : shapes) {
    Segment s(primitive_class(a.cls).make());  // each class takes the fields it has
    s.set_field("point", a.point), s.set_field("axis", Eigen::Vector3d(a.axis.normalized()));
    s.set_field("radius", a.radius), s.set_field("minor_radius", a.minor_radius);
    for (int k : a.indices) s.pixels.push_back(index[k]);
    s.inliers = s.pixels.size();
    out.push_back(std::move(s));
  }
  return out;
}

struct Method {
  std::string name, tag;  // tag: a short name for the per-frame table
  std::function<std::vector<Segment>(const Input&)> run;
  std::vector<double> ms, ms_synthetic;  // all frames; the synthetic VGA frames (full scenes)
  bench::SyntheticScore syn;
  int mosd_objects = 0, mosd_found = 0;
  std::vector<std::string> mosd_rows;
  double mug_radius_err_mm = NAN;
  int runs_left = 1 << 30;  // --mereo-only: 0 for the anchors
};

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, mereo_only = false;
  int n_syn = 20, n_real = 24;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true, n_syn = 1, n_real = 1;
    else if (a == "--mereo-only") mereo_only = true;  // for tuning: skip the anchors
    else if (a == "--synthetic" && i + 1 < argc) n_syn = std::stoi(argv[++i]);
    else if (a == "--real" && i + 1 < argc) n_real = std::stoi(argv[++i]);
  }

  std::vector<Input> inputs;
  for (int s = 0; s < n_syn; ++s) {
    auto sf = synthetic::render(std::uint64_t(900 + s));
    Input in = prepare("synthetic:" + std::to_string(900 + s), extension::back_project(sf.frame), sf.frame.color,
                       sf.frame.intrinsics.fx);
    in.truth = std::move(sf.truth);
    inputs.push_back(std::move(in));
  }
  const fs::path real = fs::path(MEREO_REAL_DATA);
  std::vector<fs::path> files;
  if (fs::is_directory(real / "pcl-mosd"))
    for (const auto& e : fs::directory_iterator(real / "pcl-mosd"))
      if (e.path().extension() == ".pcd") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (int(files.size()) > n_real) files.resize(n_real);
  for (const auto& path : files) {
    const Frame f = io::read(path.string());
    Input in = prepare(path.filename().string(), extension::back_project(f), f.color, f.intrinsics.fx);
    in.labels = f.labels;
    inputs.push_back(std::move(in));
  }
  // the real mug: its reference is a circle through the wall points above the table, trimmed
  // of the handle
  double mug_reference = NAN;
  const fs::path mug_file = real / "pcl" / "table_scene_mug_stereo_textured.pcd";
  if (fs::exists(mug_file)) {
    const Frame f = io::read(mug_file.string());
    Input in = prepare("table_scene_mug", extension::back_project(f), f.color, f.intrinsics.fx);
    const auto wall = bench::wall_points(in.cloud, in.normals, in.up, [&](std::size_t i) { return in.roi.data()[i] != 0; });
    const bench::Circle c = bench::fit_circle(wall, 0.01);
    mug_reference = c.radius;
    std::printf("real mug reference: circle through %zu wall points above the table, radius %.1f mm, RMS %.2f mm\n",
                c.points, 1000 * c.radius, 1000 * c.rms);
    inputs.push_back(std::move(in));
  }

  bench::AnchorOptions ao;  // same tolerances as mereo's defaults at 1 m
  std::vector<Method> methods;
  methods.push_back({"mereo, whole frame", "mereo", [](const Input& in) {
                       features::DetectOptions o;
                       o.focal_px = in.focal;
                       return features::detect_primitives(in.cloud, in.normals, o, &in.color);
                     }});
  methods.push_back({"cgal Efficient_RANSAC, whole frame", "cgal", [&](const Input& in) {
                       return to_segments(bench::cgal_efficient_ransac(in.points, in.point_normals, ao), in.index);
                     }});
  methods.push_back({"mereo, above the table", "mereo/roi", [](const Input& in) {
                       features::DetectOptions o;
                       o.roi = in.roi;
                       o.focal_px = in.focal;
                       return features::detect_primitives(in.cloud, in.normals, o, &in.color);
                     }});
  methods.push_back({"pcl SACSegmentationFromNormals, above", "pcl/roi", [&](const Input& in) {
                       return to_segments(bench::pcl_sac_cylinders(in.roi_points, in.roi_normals, ao), in.roi_index);
                     }});
  // the same as "mereo, above the table" with the fit by geometric distance (the anchors' kind of
  // fit) instead of along the rays: the bias table shows what the rays buy
  methods.push_back({"mereo, above, geometric fit", "mereo/geo", [](const Input& in) {
                       features::DetectOptions o;
                       o.roi = in.roi;
                       o.focal_px = in.focal;
                       o.fit_along_rays = false;
                       return features::detect_primitives(in.cloud, in.normals, o, &in.color);
                     }});
  if (mereo_only) methods[1].runs_left = methods[3].runs_left = 0;

  for (const Input& in : inputs) {
    for (Method& m : methods) {
      if (m.runs_left-- <= 0) continue;
      const double t0 = now_ms();
      const auto found = m.run(in);
      m.ms.push_back(now_ms() - t0);
      if (in.truth) m.ms_synthetic.push_back(m.ms.back());
      if (in.truth) {
        bench::score_synthetic(*in.truth, found, in.name, m.syn);
      } else if (!in.labels.empty()) {
        const auto objects = bench::mosd_cylinders(in.cloud, in.normals, in.labels, in.up);
        std::string row = in.name + ":";
        for (const auto& o : objects) {
          bool hit = false;
          for (const Segment& s : found) {
            if (!s.is<shapes::Cylinder>() || s.pixels.empty()) continue;
            int mine = 0;
            for (int i : s.pixels) mine += in.labels.data()[i] >= 20 && in.labels.data()[i] / 10 == o.object;
            hit = hit || mine >= 0.8 * s.pixels.size();
          }
          ++m.mosd_objects, m.mosd_found += hit;
          char cell[64];
          std::snprintf(cell, sizeof cell, " %u(r=%.0fmm)%s", o.object, 1000 * o.radius, hit ? "+" : "-");
          row += cell;
        }
        m.mosd_rows.push_back(row);
      } else if (std::isfinite(mug_reference)) {
        // the body: the largest cylinder of about the reference's size (the closest one could be
        // a piece of the handle taken for a small cylinder, as it was before the handle search
        // took such pieces)
        const Segment* body = nullptr;
        for (const Segment& s : found)
          if (s.is<shapes::Cylinder>() && !s.inward && std::abs(s.size() - mug_reference) < 0.02 &&
              (!body || s.pixels.size() > body->pixels.size()))
            body = &s;
        m.mug_radius_err_mm = body ? 1000 * std::abs(body->size() - mug_reference) : NAN;
      }
    }
  }

  std::printf("bench_primitives: %d synthetic frames (seeds 900-%d), %zu mOSD frames, the real mug\n\n", n_syn,
              900 + n_syn - 1, files.size());
  std::printf("%-38s %9s %8s %8s %8s %8s %8s %9s %9s %9s %8s\n", "method", "ms/frame", "bodies", "recall", "rad mm",
              "axis deg", "handles", "h.recall", "false cyl", "false tor", "mOSD");
  for (const Method& m : methods) {
    std::printf("%-38s %9.1f %4d/%-3d %8.3f %8.2f %8.2f %4d/%-3d %9.3f %9.2f %9.2f %4d/%-3d\n", m.name.c_str(),
                median(m.ms), m.syn.bodies_found, m.syn.bodies, m.syn.body_recall(), median(m.syn.radius_err_mm),
                median(m.syn.axis_err_deg), m.syn.handles_found, m.syn.handles, m.syn.handle_recall(),
                m.syn.false_cylinders_per_frame(), m.syn.frames ? double(m.syn.false_tori) / m.syn.frames : NAN,
                m.mosd_found, m.mosd_objects);
  }
  // the fit's bias: a depth sensor's noise lies along the rays; a geometric fit to a curved
  // surface under it comes out too small, more so with distance (mereo fits along the rays)
  std::printf("\nbody radius bias (mean signed error, mm) by distance from the camera:\n");
  std::printf("%-38s %12s %12s %12s\n", "method", "< 0.8 m", "0.8-1.1 m", ">= 1.1 m");
  for (const Method& m : methods)
    std::printf("%-38s %12.3f %12.3f %12.3f\n", m.name.c_str(), m.syn.mean_radius_bias_mm(0, 0.8),
                m.syn.mean_radius_bias_mm(0.8, 1.1), m.syn.mean_radius_bias_mm(1.1, 10));
  std::printf("\nmOSD upright cylindrical objects per frame (object id, reference radius, + found / - not):\n");
  for (std::size_t r = 0; r < methods[0].mosd_rows.size(); ++r)
    for (const Method& m : methods)
      if (r < m.mosd_rows.size()) std::printf("  %-10s %s\n", m.tag.c_str(), m.mosd_rows[r].c_str());
  std::printf("\nreal mug body radius error (mm):");
  for (const Method& m : methods) std::printf("  %s %.2f", m.name.c_str(), m.mug_radius_err_mm);
  std::printf("\n");
  for (const Method& m : methods) {
    if (m.tag.rfind("mereo", 0) != 0) continue;
    std::printf("missed by %s:", m.name.c_str());
    for (const auto& s : m.syn.missed) std::printf(" %s;", s.c_str());
    std::printf("\n");
  }

  auto figures = [](const Method& m) {
    using bench::json_number;
    const double false_tori = m.syn.frames ? double(m.syn.false_tori) / m.syn.frames : NAN;
    return "{\"median_ms\": " + json_number(median(m.ms), 2) + ", \"body_recall\": " + json_number(m.syn.body_recall(), 4) +
           ", \"median_radius_error_mm\": " + json_number(median(m.syn.radius_err_mm)) +
           ", \"median_axis_error_deg\": " + json_number(median(m.syn.axis_err_deg)) +
           ", \"handle_recall\": " + json_number(m.syn.handle_recall(), 4) +
           ", \"false_cylinders_per_frame\": " + json_number(m.syn.false_cylinders_per_frame()) +
           ", \"false_tori_per_frame\": " + json_number(false_tori) +
           ", \"radius_bias_mm_near\": " + json_number(m.syn.mean_radius_bias_mm(0, 0.8)) +
           ", \"radius_bias_mm_far\": " + json_number(m.syn.mean_radius_bias_mm(1.1, 10)) +
           ", \"mosd_found\": " + std::to_string(m.mosd_found) + ", \"mosd_objects\": " + std::to_string(m.mosd_objects) +
           ", \"mug_radius_error_mm\": " + json_number(m.mug_radius_err_mm) + "}";
  };
  const double vga_speedup = median(methods[1].ms_synthetic) / median(methods[0].ms_synthetic);
  std::printf("\nwhole VGA frames (synthetic): mereo %.1f ms, cgal %.1f ms: %.1fx; all frames: %.1fx; "
              "above the table: pcl / mereo %.1fx\n",
              median(methods[0].ms_synthetic), median(methods[1].ms_synthetic), vga_speedup,
              median(methods[1].ms) / median(methods[0].ms), median(methods[3].ms) / median(methods[2].ms));
  std::printf("{\"bench\": \"primitives\", \"quick\": %s, \"synthetic_frames\": %d, \"mosd_frames\": %zu, "
              "\"mereo_frame\": %s, \"cgal_frame\": %s, \"mereo_above_table\": %s, \"pcl_above_table\": %s, "
              "\"mereo_above_table_geometric_fit\": %s, "
              "\"speedup_vs_cgal_vga\": %s, \"speedup_vs_cgal\": %s, \"speedup_vs_pcl\": %s}\n",
              quick ? "true" : "false", n_syn, files.size(), figures(methods[0]).c_str(), figures(methods[1]).c_str(),
              figures(methods[2]).c_str(), figures(methods[3]).c_str(), figures(methods[4]).c_str(), bench::json_number(vga_speedup, 2).c_str(),
              bench::json_number(median(methods[1].ms) / median(methods[0].ms), 2).c_str(),
              bench::json_number(median(methods[3].ms) / median(methods[2].ms), 2).c_str());
  return 0;
}
