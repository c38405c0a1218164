// Organized PCD files through PCL (the only translation unit that includes PCL's io).
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include "mereo/core/error.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/io/io.hpp"
#include "file_util.hpp"

namespace mereo::io {

namespace {

struct PcdHeader {
  int width = -1, height = -1;
  std::size_t points = 0;
  std::size_t point_size = 0;
  std::string data;
  std::size_t data_offset = 0;
  std::vector<std::string> fields;
};

// Reads and checks the header and the body's size before PCL sees the file, so that a
// truncated or corrupt file is a clear error and never a read past the end.
PcdHeader check_pcd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  PcdHeader h;
  std::vector<std::size_t> sizes, counts;
  std::string line;
  int lineno = 0;
  bool have_data = false;
  while (!have_data && std::getline(in, line)) {
    ++lineno;
    if (lineno > 64 || line.size() > 4096)
      throw InputError(path + ": not a PCD file (no DATA line in the header)");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "FIELDS") {
      std::string f;
      while (s >> f) h.fields.push_back(f);
    } else if (key == "SIZE" || key == "COUNT") {
      std::size_t v;
      auto& dst = key == "SIZE" ? sizes : counts;
      while (s >> v) dst.push_back(v);
    } else if (key == "WIDTH") {
      s >> h.width;
    } else if (key == "HEIGHT") {
      s >> h.height;
    } else if (key == "POINTS") {
      s >> h.points;
    } else if (key == "DATA") {
      s >> h.data;
      have_data = true;
    } else if (key != "VERSION" && key != "TYPE" && key != "VIEWPOINT") {
      throw InputError(path + ": not a PCD file (line " + std::to_string(lineno) + ": '" +
                       line.substr(0, 40) + "')");
    }
  }
  if (!have_data) throw InputError(path + ": not a PCD file (no DATA line in the header)");
  if (h.width <= 0 || h.height <= 0 || h.fields.empty() || sizes.size() != h.fields.size())
    throw InputError(path + ": corrupt PCD header (FIELDS, SIZE, WIDTH or HEIGHT missing)");
  if (counts.empty()) counts.assign(sizes.size(), 1);
  if (counts.size() != sizes.size()) throw InputError(path + ": corrupt PCD header (COUNT)");
  for (std::size_t i = 0; i < sizes.size(); ++i) h.point_size += sizes[i] * counts[i];
  h.data_offset = static_cast<std::size_t>(in.tellg());
  in.seekg(0, std::ios::end);
  const std::size_t file_size = static_cast<std::size_t>(in.tellg());
  const std::size_t n = std::size_t(h.width) * std::size_t(h.height);
  const std::size_t body = file_size - h.data_offset;
  if (h.data == "binary") {
    if (body < n * h.point_size)
      throw InputError(path + ": truncated PCD file (" + std::to_string(body) + " bytes of data, " +
                       std::to_string(n * h.point_size) + " expected)");
  } else if (h.data == "binary_compressed") {
    std::uint32_t sz[2] = {0, 0};
    in.seekg(static_cast<std::streamoff>(h.data_offset));
    if (body < 8 || !in.read(reinterpret_cast<char*>(sz), 8))
      throw InputError(path + ": truncated PCD file (no compressed data)");
    if (sz[0] > body - 8)
      throw InputError(path + ": truncated PCD file (" + std::to_string(body - 8) +
                       " bytes of compressed data, " + std::to_string(sz[0]) + " expected)");
    if (sz[1] != n * h.point_size)
      throw InputError(path + ": corrupt PCD file (uncompressed size " + std::to_string(sz[1]) +
                       ", " + std::to_string(n * h.point_size) + " expected)");
  } else if (h.data != "ascii") {
    throw InputError(path + ": corrupt PCD header (DATA '" + h.data + "')");
  }
  return h;
}

const pcl::PCLPointField* field(const pcl::PCLPointCloud2& c, const std::string& name) {
  for (const auto& f : c.fields)
    if (f.name == name) return &f;
  return nullptr;
}

}  // namespace

Frame read_pcd(const std::string& path, const ReadOptions& options) {
  require_file(path);
  const PcdHeader header = check_pcd(path);
  if (header.height == 1)
    throw InputError(path + ": the PCD file is not organized (HEIGHT 1, WIDTH " +
                     std::to_string(header.width) + "); an image-shaped cloud is needed");
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  pcl::PCDReader reader;
  int version = 0;
  if (reader.read(path, blob, origin, orientation, version) < 0)
    throw InputError(path + ": corrupt PCD file (PCL could not read it)");
  const auto *fx = field(blob, "x"), *fy = field(blob, "y"), *fz = field(blob, "z");
  if (!fx || !fy || !fz)
    throw InputError(path + ": the PCD file has no x, y, z fields");
  for (const auto* f : {fx, fy, fz})
    if (f->datatype != pcl::PCLPointField::FLOAT32)
      throw InputError(path + ": field " + f->name + " is not FLOAT32");
  const pcl::PCLPointField* frgb = field(blob, "rgba");
  if (!frgb) frgb = field(blob, "rgb");
  const pcl::PCLPointField* flabel = field(blob, "label");
  if (flabel && flabel->datatype != pcl::PCLPointField::UINT32 &&
      flabel->datatype != pcl::PCLPointField::INT32)
    flabel = nullptr;

  const int rows = int(blob.height), cols = int(blob.width);
  Frame frame;
  frame.source = path;
  frame.id = file_stem(path);
  frame.cloud = Cloud(rows, cols, kNaN);
  if (frgb) frame.color = ColorImage(rows, cols, 0);
  if (flabel) frame.labels = LabelImage(rows, cols, 0);
  for (int v = 0; v < rows; ++v) {
    for (int u = 0; u < cols; ++u) {
      const std::uint8_t* pt = blob.data.data() + std::size_t(v) * blob.row_step +
                               std::size_t(u) * blob.point_step;
      float xyz[3];
      std::memcpy(&xyz[0], pt + fx->offset, 4);
      std::memcpy(&xyz[1], pt + fy->offset, 4);
      std::memcpy(&xyz[2], pt + fz->offset, 4);
      if (std::isfinite(xyz[0]) && std::isfinite(xyz[1]) && std::isfinite(xyz[2]) && xyz[2] > 0) {
        float* p = frame.cloud.ptr(v, u);
        p[0] = xyz[0], p[1] = xyz[1], p[2] = xyz[2];
      }
      if (frgb) {
        std::uint32_t c;
        std::memcpy(&c, pt + frgb->offset, 4);
        std::uint8_t* q = frame.color.ptr(v, u);
        q[0] = (c >> 16) & 0xff, q[1] = (c >> 8) & 0xff, q[2] = c & 0xff;
      }
      if (flabel) std::memcpy(&frame.labels(v, u), pt + flabel->offset, 4);
    }
  }
  frame.depth = extension::cloud_depth(frame.cloud);
  if (options.intrinsics) {
    frame.intrinsics = *options.intrinsics;
  } else {
    try {
      frame.intrinsics = extension::fit_intrinsics(frame.cloud);
    } catch (const InputError& e) {
      throw InputError(path + ": " + e.what());
    }
  }
  frame.validate();
  return frame;
}

void write_pcd(const std::string& path, const Frame& frame) {
  const Cloud cloud = extension::back_project(frame);
  const int rows = cloud.rows(), cols = cloud.cols();
  if (cloud.empty()) throw InputError(path + ": nothing to write (the frame is empty)");
  pcl::PCLPointCloud2 blob;
  blob.width = cols;
  blob.height = rows;
  blob.is_dense = false;
  const bool labels = !frame.labels.empty();
  const char* names[] = {"x", "y", "z", "rgba", "label"};
  const int nfields = labels ? 5 : 4;
  for (int i = 0; i < nfields; ++i) {
    pcl::PCLPointField f;
    f.name = names[i];
    f.offset = 4 * i;
    f.datatype = i < 3 ? pcl::PCLPointField::FLOAT32 : pcl::PCLPointField::UINT32;
    f.count = 1;
    blob.fields.push_back(f);
  }
  blob.point_step = 4 * nfields;
  blob.row_step = blob.point_step * cols;
  blob.data.resize(std::size_t(blob.row_step) * rows);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) {
      std::uint8_t* pt = blob.data.data() + std::size_t(v) * blob.row_step +
                         std::size_t(u) * blob.point_step;
      std::memcpy(pt, cloud.ptr(v, u), 12);
      std::uint32_t c = 0;
      if (!frame.color.empty()) {
        const std::uint8_t* q = frame.color.ptr(v, u);
        c = (255u << 24) | (std::uint32_t(q[0]) << 16) | (std::uint32_t(q[1]) << 8) | q[2];
      }
      std::memcpy(pt + 12, &c, 4);
      if (labels) std::memcpy(pt + 16, &frame.labels(v, u), 4);
    }
  pcl::PCDWriter writer;
  if (writer.writeBinaryCompressed(path, blob) < 0)
    throw InputError(path + ": cannot write the PCD file");
}

}  // namespace mereo::io
