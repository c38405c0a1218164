// Turns inputs (files, folders, "synthetic:SEED") into lazily loaded frame sequences.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "file_util.hpp"
#include "mereo/core/error.hpp"
#include "mereo/io/io.hpp"
#include "mereo/synthetic/scene.hpp"

namespace mereo::io {

namespace fs = std::filesystem;

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Colour/depth naming conventions: NAME_rgb.png + NAME_depth.png, NAME-color.png + NAME-depth.png.
struct PairPattern {
  const char* color;
  const char* depth;
};
// (and 7-Scenes/3DMatch: frame-NNNNNN.color.png + frame-NNNNNN.depth.png, frame-NNNNNN.pose.txt)
constexpr PairPattern kPatterns[] = {{"_rgb", "_depth"}, {"-color", "-depth"}, {"_color", "_depth"},
                                     {".color", ".depth"}};
const char* kColorExts[] = {".png", ".jpg", ".jpeg", ".ppm"};
const char* kDepthExts[] = {".png", ".pgm", ".tiff", ".exr"};

std::string find_with_ext(const fs::path& dir, const std::string& stem, const char* const* exts, int n) {
  for (int i = 0; i < n; ++i) {
    fs::path p = dir / (stem + exts[i]);
    if (fs::is_regular_file(p)) return p.string();
  }
  return {};
}

// Intrinsics, depth scale and a second depth camera for image pairs in `dir`.
struct ImageCamera {
  Intrinsics K;
  double scale;
  std::optional<DepthCamera> depth;
};
ImageCamera image_camera(const fs::path& dir, const ReadOptions& o, const std::string& what, double default_scale,
                         std::optional<Intrinsics> fallback) {
  double scale = 0;
  std::optional<Intrinsics> K = o.intrinsics;
  std::optional<DepthCamera> depth = o.depth_camera;
  // ours, NVlabs' (camera_params.json), 7-Scenes/3DMatch's (camera-intrinsics.txt, beside the
  // images or beside their sequence's folder)
  bool found = false;
  for (const fs::path& d : {dir, dir.parent_path()})
    for (const char* name : {"intrinsics.json", "camera.json", "camera_params.json", "camera-intrinsics.txt"}) {
      const fs::path p = d / name;
      if (found || (d != dir && std::string(name) != "camera-intrinsics.txt") || !fs::is_regular_file(p)) continue;
      double s = 0;
      const Intrinsics fileK = read_intrinsics(p.string(), &s);
      if (!K) K = fileK, depth = read_depth_camera(p.string());
      if (s > 0) scale = s;
      found = true;
    }
  if (!K) K = fallback;
  if (!K)
    throw InputError(what + ": no intrinsics (pass --intrinsics fx,fy,cx,cy or a JSON file, or put "
                            "intrinsics.json beside the images)");
  if (o.depth_scale > 0) scale = o.depth_scale;
  if (!(scale > 0)) scale = default_scale;
  return {*K, scale, depth};
}

/// A 7-Scenes/3DMatch pose file: the 4x4 camera-to-world matrix as text.
Pose read_pose_matrix(const std::string& path) {
  std::ifstream in(path);
  Eigen::Matrix4d M;
  for (int k = 0; k < 16; ++k)
    if (!(in >> M(k / 4, k % 4)) || !std::isfinite(M(k / 4, k % 4)))
      throw InputError(path + ": expected a 4x4 camera-to-world matrix (16 numbers)");
  if (!is_rigid(M)) throw InputError(path + ": not a rigid transform (rotation and translation, last row 0 0 0 1)");
  Pose P = Pose::Identity();
  P.linear() = M.topLeftCorner<3, 3>(), P.translation() = M.topRightCorner<3, 1>();
  return P;
}

void add_pair(Sequence& seq, const std::string& id, const std::string& color, const std::string& depth,
              const ImageCamera& camera, DepthFormat format) {
  // 7-Scenes/3DMatch: frame-N.pose.txt beside frame-N.depth.png, in a world that SLAM chose
  const fs::path pose_file = fs::path(depth).parent_path() / (id + ".pose.txt");
  const std::string pose = fs::is_regular_file(pose_file) ? pose_file.string() : std::string();
  seq.add({id, depth, [=] {
             Frame f = read_png_pair(color, depth, camera.K, camera.scale, format, camera.depth);
             f.id = id;
             if (!pose.empty()) f.pose = read_pose_matrix(pose), f.gravity_aligned = false;
             return f;
           }});
}

// The partner of one image of a pair, or "" when `path` follows no pattern.
bool split_pair(const fs::path& path, std::string& stem, std::string& color, std::string& depth) {
  const std::string s = path.stem().string();
  const fs::path dir = path.parent_path();
  for (const auto& pat : kPatterns) {
    for (const char* role : {pat.color, pat.depth}) {
      if (!ends_with(lower(s), role)) continue;
      stem = s.substr(0, s.size() - std::string(role).size());
      color = find_with_ext(dir, stem + pat.color, kColorExts, 4);
      depth = find_with_ext(dir, stem + pat.depth, kDepthExts, 4);
      if (!color.empty() && !depth.empty()) return true;
    }
  }
  return false;
}

struct Stamped {
  double t;
  std::string value;
  int line = 0;  ///< in its list file
};

std::vector<Stamped> read_list(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw InputError(p.string() + ": cannot open file");
  std::vector<Stamped> out;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    Stamped e;
    e.line = lineno;
    if (!(s >> e.t)) throw InputError(p.string() + ":" + std::to_string(lineno) + ": expected 'timestamp ...'");
    std::getline(s >> std::ws, e.value);
    if (e.value.empty()) throw InputError(p.string() + ":" + std::to_string(lineno) + ": missing value after the timestamp");
    out.push_back(e);
  }
  std::sort(out.begin(), out.end(), [](const Stamped& a, const Stamped& b) { return a.t < b.t; });
  return out;
}

// The entry of `list` (sorted by time) nearest to t, if within max_dt.
const Stamped* nearest(const std::vector<Stamped>& list, double t, double max_dt) {
  auto it = std::lower_bound(list.begin(), list.end(), t, [](const Stamped& a, double x) { return a.t < x; });
  const Stamped* best = nullptr;
  if (it != list.end()) best = &*it;
  if (it != list.begin() && (!best || t - std::prev(it)->t < best->t - t)) best = &*std::prev(it);
  return best && std::abs(best->t - t) <= max_dt ? best : nullptr;
}

void open_tum(Sequence& seq, const fs::path& dir, const ReadOptions& o) {
  const auto rgb = read_list(dir / "rgb.txt");
  const auto depth = read_list(dir / "depth.txt");
  std::vector<Stamped> gt;
  if (fs::is_regular_file(dir / "groundtruth.txt")) gt = read_list(dir / "groundtruth.txt");
  const ImageCamera camera = image_camera(dir, o, dir.string(), 5000.0, Intrinsics::kinect_vga());
  std::size_t before = seq.size();
  for (const auto& d : depth) {
    const Stamped* c = nearest(rgb, d.t, 0.02);
    if (!c) continue;
    std::optional<Pose> pose;
    if (const Stamped* g = gt.empty() ? nullptr : nearest(gt, d.t, 0.02)) {
      std::istringstream s(g->value);
      double tx, ty, tz, qx, qy, qz, qw;
      if (!(s >> tx >> ty >> tz >> qx >> qy >> qz >> qw))
        throw InputError((dir / "groundtruth.txt").string() + ":" + std::to_string(g->line) +
                         ": expected 'timestamp tx ty tz qx qy qz qw'");
      const Eigen::Quaterniond q(qw, qx, qy, qz);
      std::ostringstream bad;
      if (!(std::abs(q.norm() - 1) <= 1e-2))
        bad << "the quaternion " << qx << " " << qy << " " << qz << " " << qw << " has norm " << q.norm()
            << " (expected a unit quaternion, within 0.01)";
      else if (!Eigen::Vector3d(tx, ty, tz).allFinite())
        bad << "the translation " << tx << " " << ty << " " << tz << " is not finite";
      if (!bad.str().empty())
        throw InputError((dir / "groundtruth.txt").string() + ":" + std::to_string(g->line) + ": " + bad.str());
      Pose P = Pose::Identity();
      P.linear() = q.normalized().toRotationMatrix();
      P.translation() = Eigen::Vector3d(tx, ty, tz);
      pose = P;
    }
    std::ostringstream id_text;
    id_text.precision(6);
    id_text << std::fixed << d.t;
    const std::string id = id_text.str();
    const std::string color = (dir / c->value).string(), depth_path = (dir / d.value).string();
    const double t = d.t;
    seq.add({id, depth_path, [=] {
               Frame f = read_png_pair(color, depth_path, camera.K, camera.scale, o.depth_format, camera.depth);
               f.id = id;
               f.timestamp = t;
               f.pose = pose;
               return f;
             }});
  }
  if (seq.size() == before)
    throw InputError(dir.string() + ": no depth image in depth.txt has a colour image in rgb.txt within 0.02 s");
}

void open_folder(Sequence& seq, const fs::path& dir, const ReadOptions& o) {
  if (fs::is_regular_file(dir / "rgb.txt") && fs::is_regular_file(dir / "depth.txt"))
    return open_tum(seq, dir, o);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  const std::size_t before = seq.size();
  if (fs::is_directory(dir / "rgb") && fs::is_directory(dir / "depth")) {
    const ImageCamera camera = image_camera(dir, o, dir.string(), 1000.0, std::nullopt);
    std::vector<fs::path> depths;
    for (const auto& e : fs::directory_iterator(dir / "depth")) depths.push_back(e.path());
    std::sort(depths.begin(), depths.end());
    for (const auto& d : depths) {
      const std::string stem = d.stem().string();
      const std::string color = find_with_ext(dir / "rgb", stem, kColorExts, 4);
      if (!color.empty()) add_pair(seq, stem, color, d.string(), camera, o.depth_format);
    }
  } else {
    std::vector<std::array<std::string, 3>> pairs;
    for (const auto& p : files) {
      const std::string ext = lower(p.extension().string());
      if (ext == ".pcd") {
        const std::string path = p.string();
        seq.add({p.stem().string(), path, [path, o] { return read_pcd(path, o); }});
        continue;
      }
      std::string stem, color, depth;
      if (split_pair(p, stem, color, depth) && depth == p.string()) pairs.push_back({stem, color, depth});
    }
    if (!pairs.empty()) {
      const ImageCamera camera = image_camera(dir, o, dir.string(), 1000.0, std::nullopt);
      for (const auto& [stem, color, depth] : pairs) add_pair(seq, stem, color, depth, camera, o.depth_format);
    }
  }
  if (seq.size() == before)
    throw InputError(dir.string() + ": no frames found (expected .pcd files, NAME_rgb.png + NAME_depth.png, "
                                    "NAME-color.png + NAME-depth.png, frame-N.color.png + frame-N.depth.png, "
                                    "rgb/ + depth/ folders, or a TUM folder)");
}

void open_synthetic(Sequence& seq, const std::string& input, const ReadOptions& o) {
  const std::string text = input.substr(std::string("synthetic:").size());
  std::uint64_t seed = 0;
  std::size_t used = 0;
  try {
    if (!text.empty() && text[0] != '-') seed = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size())
    throw InputError(input + ": expected synthetic:SEED with SEED a non-negative integer");
  if (o.synthetic_frames < 1) throw InputError(input + ": the number of frames must be at least 1");
  synthetic::SceneOptions so = o.synthetic;
  if (o.intrinsics) so.intrinsics = *o.intrinsics;
  auto scene = std::make_shared<synthetic::Scene>(synthetic::generate_scene(seed, so));
  for (int i = 0; i < o.synthetic_frames; ++i) {
    char id[16];
    std::snprintf(id, sizeof id, "%04d", i);
    seq.add({id, input, [scene, so, i] {
               return synthetic::render(*scene, synthetic::orbit_view(*scene, i, so), so, i).frame;
             }});
  }
}

}  // namespace

Sequence open(const std::vector<std::string>& inputs, const ReadOptions& options) {
  if (inputs.empty()) throw InputError("no input given");
  if (options.depth_scale != 0) checked_depth_scale(options.depth_scale, "depth_scale (--depth-scale)");  // (0: not given)
  Sequence seq;
  for (const auto& input : inputs) {
    if (input.rfind("synthetic:", 0) == 0) {
      open_synthetic(seq, input, options);
      continue;
    }
    std::error_code ec;
    if (!fs::exists(input, ec)) throw InputError(input + ": no such file or folder");
    if (fs::is_directory(input, ec)) {
      open_folder(seq, input, options);
      continue;
    }
    const fs::path p(input);
    if (lower(p.extension().string()) == ".pcd") {
      seq.add({p.stem().string(), input, [input, options] { return read_pcd(input, options); }});
      continue;
    }
    std::string stem, color, depth;
    if (!split_pair(p, stem, color, depth))
      throw InputError(input + ": unknown input (expected a .pcd file, NAME_depth.png with NAME_rgb.png, "
                               "NAME-depth.png with NAME-color.png, a folder, or synthetic:SEED)");
    add_pair(seq, stem, color, depth, image_camera(p.parent_path(), options, input, 1000.0, std::nullopt),
             options.depth_format);
  }
  return seq;
}

Frame read(const std::string& input, const ReadOptions& options) {
  return open({input}, options).load(0);
}

}  // namespace mereo::io
