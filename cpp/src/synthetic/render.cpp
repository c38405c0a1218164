// Ray casting of a synthetic scene: exact ground truth, colour, and the depth models (the
// Kinect-like one here, the active-stereo one in depth_stereo.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mereo/synthetic/scene.hpp"
#include "depth_models.hpp"
#include "raycast.hpp"

namespace mereo::synthetic {

using detail::Bound;
using detail::Hit;
using detail::Kind;
using detail::Prim;
using detail::RayHit;
using detail::RenderObject;
using detail::RenderScene;
using detail::Vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kBaseline = 0.075;  // projector-camera baseline, metres (projector at +x)

/// Camera-frame primitives of the scene, and the ground-truth part list.
RenderScene build(const Scene& scene, const Pose& camera_pose, std::vector<ObjectTruth>& truth) {
  const Pose world_to_camera = camera_pose.inverse();
  RenderScene rs;
  std::uint32_t label = 0;
  truth.clear();
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& so = scene.objects[i];
    ObjectTruth ot;
    ot.id = std::uint32_t(i + 1);
    ot.model = so.model;
    ot.pose = so.pose;
    ot.kind = so.kind;
    RenderObject ro;
    ro.id = ot.id;
    ro.color = so.color;
    ro.first = int(rs.prims.size());
    const Shape* body = nullptr;
    if (so.model == "mug")
      for (const auto& [role, shape] : so.parts)
        if (role == "body") body = &shape;
    for (const auto& [role, shape] : so.parts) {
      PartTruth pt;
      pt.role = role;
      pt.world = shape;
      pt.camera = shape.transformed(world_to_camera);
      pt.label = ++label;
      const std::size_t first = rs.prims.size();
      detail::append_prims(pt.camera, rs.prims);
      for (std::size_t k = first; k < rs.prims.size(); ++k) {
        Prim& p = rs.prims[k];
        p.label = pt.label;
        p.object = ot.id;
        if (body == nullptr || role != "handle") continue;
        // A mug handle: hide what is inside the body (the ends that go into the wall).
        const Shape bc = body->transformed(world_to_camera);
        p.clip = true;
        p.clip_c = bc.point;
        p.clip_a = bc.axis.normalized();
        p.clip_r = bc.radius;
        p.clip_half_h = 0.5 * bc.height;
        if (pt.camera.cls != "torus") continue;
        // A torus arc: the arc only excludes the inner side of the ring (every point of the
        // tube where the centre circle is closer to the body axis than R - minor lies inside
        // the body).
        const Vec3 w = p.c - p.clip_c;
        const double dist = (w - w.dot(p.clip_a) * p.clip_a).norm();
        const double x = std::clamp((bc.radius - p.r_in - dist) / p.r, -1.0, 1.0);
        const double half = std::acos(x);
        p.arc0 = -half;
        p.arc_len = 2 * half;
      }
      ot.parts.push_back(std::move(pt));
    }
    ro.count = int(rs.prims.size()) - ro.first;
    // bounding sphere of the object (unbounded if it has a plane)
    bool unbounded = false;
    Vec3 c = Vec3::Zero();
    for (int k = ro.first; k < ro.first + ro.count; ++k) {
      const Bound b = detail::bound_of(rs.prims[k]);
      if (b.r < 0) unbounded = true;
      c += b.c;
    }
    if (unbounded || ro.count == 0) {
      ro.bound.r = -1;
    } else {
      c /= ro.count;
      double r = 0;
      for (int k = ro.first; k < ro.first + ro.count; ++k) {
        const Bound b = detail::bound_of(rs.prims[k]);
        r = std::max(r, (b.c - c).norm() + b.r);
      }
      ro.bound.c = c;
      ro.bound.r = r * (1 + 1e-9) + 1e-9;
    }
    rs.objects.push_back(ro);
    truth.push_back(std::move(ot));
  }
  return rs;
}

// per-pixel noise streams
enum Stream : std::uint64_t {
  kAngle = 1, kEdge = 2, kGauss1 = 3, kGauss2 = 4, kColor1 = 5, kColor2 = 6
};

inline double pixel_uniform(std::uint64_t seed, int frame, std::size_t pixel, Stream s) {
  return detail::unit_from_bits(
      detail::hash4(seed, std::uint64_t(std::int64_t(frame)), std::uint64_t(pixel), s));
}

inline double pixel_gauss(std::uint64_t seed, int frame, std::size_t pixel, Stream s1,
                          Stream s2, double& second) {
  const double u1 = 1.0 - pixel_uniform(seed, frame, pixel, s1);  // (0, 1]
  const double u2 = pixel_uniform(seed, frame, pixel, s2);
  const double m = std::sqrt(-2.0 * std::log(u1));
  second = m * std::sin(2 * kPi * u2);
  return m * std::cos(2 * kPi * u2);
}

std::string frame_name(int index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%04d", index);
  return buf;
}

}  // namespace

SyntheticFrame render(const Scene& scene, const Pose& camera_pose, const SceneOptions& options,
                      int frame_index) {
  const int W = options.width, H = options.height;
  if (W <= 0 || H <= 0) throw std::invalid_argument("synthetic::render: image size must be positive");
  const Intrinsics K = options.intrinsics;
  if (!K.valid()) throw std::invalid_argument("synthetic::render: intrinsics must be positive");

  SyntheticFrame out;
  GroundTruth& gt = out.truth;
  gt.camera_pose = camera_pose;
  const RenderScene rs = build(scene, camera_pose, gt.objects_truth);

  gt.depth = DepthImage(H, W, kNaN);
  gt.normals = NormalMap(H, W, kNaN);
  gt.objects = LabelImage(H, W, 0u);
  gt.parts = LabelImage(H, W, 0u);
  std::vector<float> shade(std::size_t(W) * H, 0.0f);  // Lambertian factor
  std::vector<double> ray_t(std::size_t(W) * H, 0.0);  // exact hit distance
  std::vector<int> hit_obj(std::size_t(W) * H, -1);

  auto ray_dir = [&](int u, int v) {
    return Vec3((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0).normalized();
  };

  // ---- primary rays: exact ground truth ----
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      for (int u = 0; u < W; ++u) {
        const Vec3 d = ray_dir(u, v);
        RayHit hit;
        if (!cast_nearest(rs, Vec3::Zero(), d, 0.0, std::numeric_limits<double>::infinity(), hit))
          continue;
        Vec3 n = hit.n;
        if (n.dot(d) > 0) n = -n;
        const std::size_t i = std::size_t(v) * W + u;
        gt.depth(v, u) = float(hit.t * d.z());
        float* np = gt.normals.ptr(v, u);
        np[0] = float(n.x());
        np[1] = float(n.y());
        np[2] = float(n.z());
        gt.objects(v, u) = hit.object;
        gt.parts(v, u) = hit.label;
        shade[i] = float(-n.dot(d));
        ray_t[i] = hit.t;
        hit_obj[i] = hit.obj_index;
      }
    }
  });
  std::uint32_t max_label = 0;  // the highest part label (labels index the per-part counts)
  for (const auto& o : gt.objects_truth)
    for (const auto& p : o.parts) max_label = std::max(max_label, p.label);
  // rooms: the pixels each object, and each part, would cover alone (its share hidden by what
  // stands in front: for a part, its own object's other parts too, as a chair's back hides its seat)
  if (scene.room) {
    std::vector<std::size_t> alone(gt.objects_truth.size() + 1, 0), alone_part(max_label + 1, 0);
    std::mutex m;
    tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
      std::vector<std::size_t> local(alone.size(), 0), local_part(alone_part.size(), 0);
      std::vector<std::uint32_t> hit, parts;
      for (int v = rows.begin(); v < rows.end(); ++v)
        for (int u = 0; u < W; ++u) {
          objects_hit(rs, Vec3::Zero(), ray_dir(u, v), hit, parts);
          for (std::uint32_t id : hit) ++local[id];
          for (std::uint32_t l : parts)
            if (l < local_part.size()) ++local_part[l];
        }
      const std::lock_guard<std::mutex> lock(m);
      for (std::size_t k = 0; k < alone.size(); ++k) alone[k] += local[k];
      for (std::size_t k = 0; k < alone_part.size(); ++k) alone_part[k] += local_part[k];
    });
    for (auto& o : gt.objects_truth) {
      o.unoccluded_pixels = alone[o.id];
      for (auto& p : o.parts) p.unoccluded_pixels = alone_part[p.label];
    }
  }

  // ---- visible pixel counts ----
  {
    std::vector<std::size_t> part_count(max_label + 1, 0), obj_count(gt.objects_truth.size() + 1, 0);
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<Vec3> lo(gt.objects_truth.size() + 1, Vec3::Constant(inf)), hi(lo.size(), Vec3::Constant(-inf));
    for (std::size_t i = 0; i < gt.parts.pixels(); ++i) {
      ++part_count[gt.parts.data()[i]];
      const std::uint32_t id = gt.objects.data()[i];
      ++obj_count[id];
      if (id == 0) continue;
      const Vec3 P = ray_t[i] * ray_dir(int(i % std::size_t(W)), int(i / std::size_t(W)));
      lo[id] = lo[id].cwiseMin(P);
      hi[id] = hi[id].cwiseMax(P);
    }
    for (auto& o : gt.objects_truth) {
      o.visible_pixels = obj_count[o.id];
      for (auto& p : o.parts) p.visible_pixels = part_count[p.label];
      if (o.visible_pixels > 0) o.visible_min = lo[o.id], o.visible_max = hi[o.id];
    }
  }

  // ---- colour and (noisy) depth ----
  Frame& f = out.frame;
  f.id = frame_name(frame_index);
  f.source = "synthetic:" + std::to_string(scene.seed);
  f.timestamp = frame_index / 30.0;
  f.intrinsics = K;
  f.pose = camera_pose;
  f.color = ColorImage(H, W, 0);
  f.depth = options.noise ? DepthImage(H, W, kNaN) : gt.depth.clone();
  const std::uint64_t seed = scene.seed;
  const DepthImage& clean = gt.depth;
  const double fb = K.fx * kBaseline;
  const Vec3 projector(kBaseline, 0.0, 0.0);

  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      for (int u = 0; u < W; ++u) {
        const std::size_t i = std::size_t(v) * W + u;
        // colour: Lambertian, light at the camera, a little ambient
        std::uint8_t* c = f.color.ptr(v, u);
        if (hit_obj[i] >= 0) {
          const Eigen::Vector3f& base = rs.objects[hit_obj[i]].color;
          const float s = 0.2f + 0.8f * std::max(0.0f, shade[i]);
          double cn = 0.0, unused = 0.0;
          if (options.noise) cn = 2.0 * pixel_gauss(seed, frame_index, i, kColor1, kColor2, unused);
          for (int ch = 0; ch < 3; ++ch) {
            const double val = 255.0 * base[ch] * s + cn;
            c[ch] = std::uint8_t(std::clamp(std::lround(val), 0l, 255l));
          }
        }
        if (!options.noise || options.depth_model != DepthModel::Kinect) continue;
        const float z0 = clean(v, u);
        if (std::isnan(z0)) continue;
        // (3) oblique surfaces: missing with probability rising from 70 to 85 degrees
        const double ang = std::acos(std::clamp(double(shade[i]), 0.0, 1.0)) * 180.0 / kPi;
        const double p_angle = std::clamp((ang - 70.0) / 15.0, 0.0, 1.0);
        if (p_angle > 0 && pixel_uniform(seed, frame_index, i, kAngle) < p_angle) continue;
        // (4) depth edges: an edge pixel is dropped with probability 0.5, and then so is its
        // neighbour across the edge on the far side
        {
          bool drop = false;
          bool edge = false;
          const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
          for (int k = 0; k < 4 && !drop; ++k) {
            const int uu = u + du[k], vv = v + dv[k];
            if (uu < 0 || vv < 0 || uu >= W || vv >= H) continue;
            const float zn = clean(vv, uu);
            if (std::isnan(zn)) {
              edge = true;
              continue;
            }
            if (std::abs(zn - z0) > 0.03f * z0) edge = true;
            // a nearer neighbour across an edge: this pixel is its far-side neighbour
            if (z0 - zn > 0.03f * zn &&
                pixel_uniform(seed, frame_index, std::size_t(vv) * W + uu, kEdge) < 0.5)
              drop = true;
          }
          if (drop) continue;
          if (edge && pixel_uniform(seed, frame_index, i, kEdge) < 0.5) continue;
        }
        // (5) projector shadow
        const Vec3 d = ray_dir(u, v);
        const Vec3 P = ray_t[i] * d;
        Vec3 to = projector - P;
        const double dist = to.norm();
        to /= dist;
        if (cast_any(rs, P, to, 1e-5, dist - 1e-6)) continue;
        // (1) axial noise (Nguyen, Izadi, Lovell 2012) and (2) disparity quantization
        double unused = 0.0;
        const double sigma = 0.0012 + 0.0019 * (z0 - 0.4) * (z0 - 0.4);
        double z = z0 + sigma * pixel_gauss(seed, frame_index, i, kGauss1, kGauss2, unused);
        if (!(z > 0.05)) continue;
        const double disparity = std::round(fb / z * 8.0) / 8.0;
        if (!(disparity > 0)) continue;
        z = fb / disparity;
        f.depth(v, u) = float(z);
      }
    }
  });
  if (options.noise && options.depth_model == DepthModel::Stereo) {
    const detail::RenderedRays rays{rs, K, clean, shade, ray_t, hit_obj, seed, frame_index};
    detail::stereo_depth(rays, options.stereo, f.depth);
  }
  return out;
}

SyntheticFrame render(std::uint64_t seed, const SceneOptions& options) {
  const Scene scene = generate_scene(seed, options);
  const Pose pose = orbit_pose(scene.look_at, scene.camera_distance, scene.camera_elevation_deg,
                               scene.camera_azimuth_deg);
  return render(scene, pose, options, 0);
}

std::vector<SyntheticFrame> render_sequence(std::uint64_t seed, int frames,
                                            const SceneOptions& options) {
  if (frames < 0) throw std::invalid_argument("synthetic::render_sequence: negative frame count");
  const Scene scene = generate_scene(seed, options);
  std::vector<SyntheticFrame> out;
  out.reserve(std::size_t(frames));
  for (int k = 0; k < frames; ++k) {
    out.push_back(render(scene, orbit_view(scene, k, options), options, k));
  }
  return out;
}

}  // namespace mereo::synthetic
