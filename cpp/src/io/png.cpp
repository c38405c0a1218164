// Colour/depth image pairs through OpenCV's imgcodecs.
#include <algorithm>
#include <cmath>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "file_util.hpp"
#include "mereo/core/error.hpp"
#include "mereo/io/io.hpp"
#include "mereo/signal/register.hpp"

namespace mereo::io {

namespace fs = std::filesystem;

namespace {

/// The most pixels an image may have (as for PCD files: 8K x 4K).
constexpr long long kMaxPixels = 1LL << 25;

/// Width and height from a file's first bytes, the header of a PNG, PNM (PPM, PGM) or JPEG (0, 0 for any other
/// format, or a header too short to tell; -1, -1 for a corrupt one: a PNG without IHDR first, a
/// PNM header that is not two numbers). OpenCV allocates what a header claims before it
/// decodes (up to 2^30 pixels, a limit fixed when it loads): a corrupt PPM header took 2.3 GB
/// under the fuzzer.
std::pair<long long, long long> header_size(const std::string& head) {
  const auto* b = reinterpret_cast<const unsigned char*>(head.data());
  auto be = [&](std::size_t i, int n) {
    long long v = 0;
    for (int k = 0; k < n; ++k) v = (v << 8) | b[i + k];
    return v;
  };
  if (head.size() >= 24 && head.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0)  // the IHDR chunk comes first
    return head.compare(12, 4, "IHDR") == 0 ? std::pair{be(16, 4), be(20, 4)} : std::pair{-1LL, -1LL};
  if (head.size() >= 3 && head[0] == 'P' && head[1] >= '1' && head[1] <= '6') {  // PNM: P6 W H ...
    // strictly: whitespace (or # comments) and decimal numbers; OpenCV reads past other bytes
    std::size_t i = 2;
    long long dims[2] = {-1, -1};
    for (long long& v : dims) {
      while (i < head.size() && (std::isspace(b[i]) || b[i] == '#'))
        if (b[i] == '#') i = std::min(head.find('\n', i), head.size());
        else ++i;
      const std::size_t start = i;
      for (v = 0; i < head.size() && std::isdigit(b[i]) && v < (1LL << 40); ++i) v = v * 10 + (b[i] - '0');
      if (i == start || i >= head.size() || !std::isspace(b[i])) return {-1, -1};
    }
    return {dims[0], dims[1]};
  }
  if (head.size() >= 4 && b[0] == 0xff && b[1] == 0xd8) {  // JPEG: the first frame header (SOFn)
    for (std::size_t i = 2; i + 9 < head.size();) {
      if (b[i] != 0xff) break;
      const int marker = b[i + 1];
      if (marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc)
        return {be(i + 7, 2), be(i + 5, 2)};
      i += 2 + std::size_t(be(i + 2, 2));
    }
  }
  return {0, 0};
}

/// Whether a file starts with the signature of a format read here: PNG, PNM, JPEG, TIFF or
/// OpenEXR. OpenCV picks its decoder by the signature, and some decoders abort the process on a
/// corrupt file rather than fail (a DICOM header, read through GDCM, asserted under the fuzzer).
bool known_format(const std::string& head) {
  if (head.size() < 4) return false;
  const auto* b = reinterpret_cast<const unsigned char*>(head.data());
  const auto is = [&](std::initializer_list<int> sig) { return std::equal(sig.begin(), sig.end(), b); };
  return is({0x89, 'P', 'N', 'G'}) || (b[0] == 'P' && b[1] >= '1' && b[1] <= '6') || is({0xff, 0xd8, 0xff}) ||
         is({'I', 'I', 42, 0}) || is({'M', 'M', 0, 42}) || is({0x76, 0x2f, 0x31, 0x01});
}

cv::Mat read_image(const std::string& path, int flags) {
  require_file(path);
  std::string head(64 * 1024, '\0');  // the file's first 64 KB: its signature and header
  {
    std::ifstream in(path, std::ios::binary);
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(std::size_t(in.gcount()));
  }
  if (!known_format(head)) throw InputError(path + ": not a PNG, PNM, JPEG, TIFF or OpenEXR image");
  const auto [w, h] = header_size(head);
  if (w < 0) throw InputError(path + ": cannot decode the image (corrupt header)");
  if (w > kMaxPixels || h > kMaxPixels || w * h > kMaxPixels)  // (each first: no overflow)
    throw InputError(path + ": the image's header says " + std::to_string(w) + "x" + std::to_string(h) +
                     " pixels, more than " + std::to_string(kMaxPixels));
  cv::Mat m;
  try {
    m = cv::imread(path, flags);
  } catch (const cv::Exception&) {
    m.release();
  }
  if (m.empty())
    throw InputError(path + ": cannot decode the image (corrupt or not an image)");
  return m;
}

}  // namespace

DepthFormat depth_format(const std::string& name) {
  if (name == "units" || name.empty()) return DepthFormat::Units;
  if (name == "sun3d") return DepthFormat::Sun3d;
  if (name == "nyu-raw") return DepthFormat::NyuRaw;
  throw InputError("depth format '" + name + "' is not one of: units, sun3d, nyu-raw");
}

namespace {
/// Metres of a 16-bit depth value in `format` (0 = none).
float depth_metres(std::uint16_t v, DepthFormat format, float inv_scale) {
  switch (format) {
    case DepthFormat::Sun3d: return std::uint16_t((v >> 3) | (v << 13)) * inv_scale;
    case DepthFormat::NyuRaw: {
      const int raw = ((v & 0xff) << 8) | (v >> 8);  // the payload is little-endian
      return raw < 2047 ? float(351.3 / (1092.5 - raw)) : 0.f;
    }
    case DepthFormat::Units: break;
  }
  return v * inv_scale;
}
}  // namespace

Frame read_png_pair(const std::string& color_path, const std::string& depth_path,
                    const Intrinsics& intrinsics, double depth_scale, DepthFormat format,
                    const std::optional<DepthCamera>& depth_camera) {
  checked_depth_scale(depth_scale, depth_path);
  const cv::Mat bgr = read_image(color_path, cv::IMREAD_COLOR);
  const cv::Mat raw = read_image(depth_path, cv::IMREAD_UNCHANGED);
  // depth is one channel of 16-bit units or 32-bit float metres; an 8-bit or colour image is
  // most likely a visualisation of depth, whose values are not distances
  if (raw.channels() != 1 || (raw.depth() != CV_16U && raw.depth() != CV_32F))
    throw InputError(depth_path + ": a depth image must have one channel of 16-bit units or 32-bit float metres, "
                     "this one has " + std::to_string(raw.channels()) + " channel(s) of " +
                     (raw.depth() == CV_8U ? "8-bit" : raw.depth() == CV_16U ? "16-bit" : "other") + " values");
  if (bgr.size() != raw.size() && !depth_camera)
    throw InputError(depth_path + ": depth is " + std::to_string(raw.cols) + "x" +
                     std::to_string(raw.rows) + " but colour " + color_path + " is " +
                     std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows));
  Frame frame;
  frame.source = depth_path;
  frame.intrinsics = intrinsics;
  frame.color = ColorImage(bgr.rows, bgr.cols);
  cv::Mat rgb(bgr.rows, bgr.cols, CV_8UC3, frame.color.data());
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  frame.depth = DepthImage(raw.rows, raw.cols, kNaN);
  const float inv = float(1.0 / depth_scale);
  for (int v = 0; v < raw.rows; ++v) {
    float* d = frame.depth.ptr(v, 0);
    for (int u = 0; u < raw.cols; ++u) {
      float z;
      switch (raw.depth()) {
        case CV_16U: z = depth_metres(raw.at<std::uint16_t>(v, u), format, inv); break;
        default: z = raw.at<float>(v, u); break;  // float depth is in metres already
      }
      if (valid_depth(z)) d[u] = z;
    }
  }
  if (depth_camera) {
    try {
      frame.depth = signal::register_depth(frame.depth, *depth_camera, intrinsics, bgr.rows, bgr.cols);
    } catch (const InputError& e) {
      throw InputError(depth_path + ": " + e.what());
    }
  }
  frame.validate();
  return frame;
}

std::vector<std::string> write_png_pair(const std::string& dir, const std::string& name,
                                        const Frame& frame, double depth_scale) {
  frame.validate();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw InputError(dir + ": cannot create the folder");
  const std::string color_path = (fs::path(dir) / (name + "_rgb.png")).string();
  const std::string depth_path = (fs::path(dir) / (name + "_depth.png")).string();
  const int rows = frame.rows(), cols = frame.cols();
  cv::Mat depth(rows, cols, CV_16UC1);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) {
      const float z = frame.depth(v, u);
      double units = std::isfinite(z) && z > 0 ? std::round(z * depth_scale) : 0.0;
      if (units > 65535)
        throw InputError(depth_path + ": depth " + std::to_string(z) +
                         " m does not fit 16 bits at depth scale " + std::to_string(depth_scale));
      depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(units);
    }
  cv::Mat bgr(rows, cols, CV_8UC3, cv::Scalar(0, 0, 0));
  if (!frame.color.empty()) {
    const cv::Mat rgb(rows, cols, CV_8UC3, const_cast<std::uint8_t*>(frame.color.data()));
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  }
  if (!cv::imwrite(color_path, bgr)) throw InputError(color_path + ": cannot write");
  if (!cv::imwrite(depth_path, depth)) throw InputError(depth_path + ": cannot write");
  nlohmann::json j = {{"fx", frame.intrinsics.fx}, {"fy", frame.intrinsics.fy},
                      {"cx", frame.intrinsics.cx}, {"cy", frame.intrinsics.cy},
                      {"width", cols}, {"height", rows}, {"depth_scale", depth_scale}};
  std::ofstream((fs::path(dir) / "intrinsics.json").string()) << j.dump(2) << "\n";
  return {color_path, depth_path};
}

Intrinsics read_intrinsics(const std::string& text_or_path, double* depth_scale) {
  std::error_code ec;
  if (!fs::is_regular_file(text_or_path, ec)) {
    if (text_or_path.find(',') == std::string::npos)
      throw InputError(text_or_path + ": no such intrinsics file (or give fx,fy,cx,cy)");
    return Intrinsics::parse(text_or_path);
  }
  // 7-Scenes/3DMatch's camera-intrinsics.txt: the 3x3 matrix as text
  auto matrix_text = [&]() -> std::optional<Intrinsics> {
    std::ifstream text(text_or_path);
    double m[9];
    int n = 0;
    while (n < 9 && text >> m[n]) ++n;
    std::string rest;
    if (n != 9 || (text >> rest) || m[1] != 0 || m[3] != 0 || m[6] != 0 || m[7] != 0 || m[8] != 1) return std::nullopt;
    return Intrinsics{m[0], m[4], m[2], m[5]};
  };
  std::ifstream in(text_or_path);
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {  // a syntax error, or a number beyond a double (out_of_range)
    if (const auto K = matrix_text(); K && K->valid()) return *K;
    const auto* p = dynamic_cast<const nlohmann::json::parse_error*>(&e);
    throw InputError(text_or_path + ": not valid JSON (" + (p ? "byte " + std::to_string(p->byte) : std::string("a number out of range")) +
                     ") nor a 3x3 camera matrix");
  }
  if (!j.is_object())
    if (const auto K = matrix_text(); K && K->valid()) return *K;
  // Either {"fx":..} or {"K": [[fx,0,cx],[0,fy,cy],[0,0,1]]}.
  auto number = [&](const char* key) -> double {
    if (!j.contains(key)) throw InputError(text_or_path + ": missing field '" + key + "'");
    if (!j[key].is_number()) throw InputError(text_or_path + ": field '" + key + "' is not a number");
    return j[key].get<double>();
  };
  Intrinsics K;
  if (!j.is_object()) throw InputError(text_or_path + ": expected a JSON object with fx, fy, cx, cy");
  if (j.contains("K") && !j.contains("fx")) {
    const auto& m = j["K"];
    if (!m.is_array() || m.size() != 3)
      throw InputError(text_or_path + ": field 'K' must be a 3x3 matrix");
    try {
      K = {m[0][0].get<double>(), m[1][1].get<double>(), m[0][2].get<double>(), m[1][2].get<double>()};
    } catch (const nlohmann::json::exception&) {
      throw InputError(text_or_path + ": field 'K' must be a 3x3 matrix of numbers");
    }
  } else if (!j.contains("cx") && j.contains("x_offset")) {  // NVlabs' camera_params.json
    K = {number("fx"), number("fy"), number("x_offset"), number("y_offset")};
  } else {
    K = {number("fx"), number("fy"), number("cx"), number("cy")};
  }
  if (const std::string p = K.problem(); !p.empty()) throw InputError(text_or_path + ": " + p);
  if (depth_scale && j.contains("depth_scale"))
    *depth_scale = checked_depth_scale(number("depth_scale"), text_or_path + ": field 'depth_scale'");
  return K;
}

std::optional<DepthCamera> read_depth_camera(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return std::nullopt;
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("depth_camera")) return std::nullopt;
  const auto& d = j["depth_camera"];
  const std::string what = path + ": field 'depth_camera'";
  if (!d.is_object()) throw InputError(what + " must be an object with fx, fy, cx, cy and to_color");
  auto number = [&](const char* key) -> double {
    if (!d.contains(key) || !d[key].is_number()) throw InputError(what + ": missing number '" + key + "'");
    return d[key].get<double>();
  };
  DepthCamera cam;
  cam.intrinsics = {number("fx"), number("fy"), number("cx"), number("cy")};
  if (const std::string p = cam.intrinsics.problem(); !p.empty()) throw InputError(what + ": " + p);
  const auto& m = d.contains("to_color") ? d["to_color"] : nlohmann::json();
  Eigen::Matrix4d T;
  bool ok = m.is_array() && m.size() == 4;
  for (int r = 0; ok && r < 4; ++r) {
    ok = m[r].is_array() && m[r].size() == 4;
    for (int c = 0; ok && c < 4; ++c) {
      ok = m[r][c].is_number();
      if (ok) T(r, c) = m[r][c].get<double>();
    }
  }
  if (!ok) throw InputError(what + ": 'to_color' must be a 4x4 matrix of numbers (rows)");
  if (!is_rigid(T))
    throw InputError(what + ": 'to_color' is not a rigid transform (a rotation, a translation, last row 0 0 0 1)");
  cam.to_color.matrix() = T;
  return cam;
}

}  // namespace mereo::io
