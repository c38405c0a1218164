// mereo/io/io.hpp: the hardware layer, frame sources and writers.
//
// Inputs: organized PCD files, colour/depth PNG pairs (one pair, or a folder of them),
// TUM RGB-D folders, and "synthetic:SEED" (the built-in renderer). Every reader throws
// mereo::InputError with one line that names the file and says what is wrong.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mereo/core/frame.hpp"
#include "mereo/synthetic/scene.hpp"

namespace mereo::io {

/// How a 16-bit depth image stores depth: plain units (depth_scale per metre, the common case);
/// SUN3D's bit-rotated units ((v >> 3) | (v << 13), then millimetres); NYU Depth v2's raw Kinect
/// values (a PGM whose payload is little-endian, 2047 = none; metres = 351.3 / (1092.5 - raw), as
/// Open3D's NYU reader). The files do not say which: the caller does.
enum class DepthFormat { Units, Sun3d, NyuRaw };
/// "units", "sun3d", "nyu-raw"; throws InputError listing them.
DepthFormat depth_format(const std::string& name);

struct ReadOptions {
  /// Intrinsics for image inputs; when unset: intrinsics.json beside the images, TUM's
  /// default (525, 525, 319.5, 239.5) for TUM folders, a fit to the cloud for PCD files.
  std::optional<Intrinsics> intrinsics;
  /// Depth units per metre for 16-bit depth images; 0 = the format's default
  /// (intrinsics.json's "depth_scale" or 1000 for PNG pairs, 5000 for TUM folders).
  double depth_scale = 0.0;
  DepthFormat depth_format = DepthFormat::Units;  ///< 16-bit depth images: see DepthFormat
  /// Image pairs whose depth comes from a second camera: its intrinsics and its transform to the
  /// colour camera (`intrinsics` are then the colour camera's); the depth is registered to the
  /// colour image. When unset: the "depth_camera" of the intrinsics file, if it has one.
  std::optional<DepthCamera> depth_camera;
  /// "synthetic:SEED": number of frames (the camera orbits the table), and the scene's options
  /// (noise and depth model, distractors, ...; its intrinsics give way to `intrinsics` when set).
  int synthetic_frames = 1;
  synthetic::SceneOptions synthetic;
};

/// A sequence of frames loaded lazily, in order: each entry knows its id, the file (or
/// generator) it comes from, and how to load it.
class Sequence {
 public:
  struct Entry {
    std::string id;
    std::string source;
    std::function<Frame()> load;
  };
  std::size_t size() const { return entries_.size(); }
  const Entry& at(std::size_t i) const { return entries_.at(i); }
  /// Loads frame i (throws InputError naming the file on bad input).
  Frame load(std::size_t i) const { return entries_.at(i).load(); }
  void add(Entry e) { entries_.push_back(std::move(e)); }

 private:
  std::vector<Entry> entries_;
};

/// Opens one or more inputs (files, folders, "synthetic:SEED") as one sequence.
Sequence open(const std::vector<std::string>& inputs, const ReadOptions& options = {});
/// The first frame of `input`.
Frame read(const std::string& input, const ReadOptions& options = {});

/// Reads an organized PCD file (fields x y z, optional rgb/rgba and label). The depth is the
/// cloud's z; the intrinsics are options.intrinsics or a least-squares fit to the cloud.
Frame read_pcd(const std::string& path, const ReadOptions& options = {});
/// Writes the frame's cloud (or the back-projection of its depth) with colour (and labels, if
/// any) as a binary-compressed organized PCD file.
void write_pcd(const std::string& path, const Frame& frame);

/// Reads a colour PNG/JPEG/PPM and a 16-bit (or 32-bit float, metres) depth image. With
/// `depth_camera`, the depth image is that camera's (any size) and is registered to the colour
/// camera (`intrinsics`) before it meets the colour (signal::register_depth).
Frame read_png_pair(const std::string& color_path, const std::string& depth_path,
                    const Intrinsics& intrinsics, double depth_scale,
                    DepthFormat format = DepthFormat::Units,
                    const std::optional<DepthCamera>& depth_camera = std::nullopt);
/// Writes DIR/NAME_rgb.png, DIR/NAME_depth.png (16-bit, `depth_scale` units per metre, 0 =
/// missing) and DIR/intrinsics.json. Returns the two paths written.
std::vector<std::string> write_png_pair(const std::string& dir, const std::string& name,
                                        const Frame& frame, double depth_scale = 1000.0);

/// Intrinsics from "fx,fy,cx,cy" or a JSON file {"fx":..,"fy":..,"cx":..,"cy":..} (a
/// "depth_scale" there is returned through `depth_scale` when given).
Intrinsics read_intrinsics(const std::string& text_or_path, double* depth_scale = nullptr);
/// The "depth_camera" of a JSON intrinsics file, when it has one: {"fx", "fy", "cx", "cy",
/// "to_color": 4x4 rigid transform from the depth camera's frame to the colour camera's, rows}
/// (the file's own fx, fy, cx, cy are the colour camera's). Throws InputError on a malformed one.
std::optional<DepthCamera> read_depth_camera(const std::string& path);

}  // namespace mereo::io
