// Organized PCD files: header and body read and checked here, before anything of the size a file
// claims is allocated; PCL (this is the only translation unit that includes its io) decodes LZF
// and writes.
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/lzf.h>
#include <pcl/io/pcd_io.h>

#include "mereo/core/error.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/io/io.hpp"
#include "file_util.hpp"

namespace mereo::io {

namespace {

// Limits of a header that mereo reads: an image of at most 2^25 points (8K x 4K), PCL's field
// sizes and types, and counts far beyond any descriptor's (FPFH has 33).
constexpr long long kMaxSide = 1 << 16, kMaxPoints = 1LL << 25, kMaxCount = 4096, kMaxFields = 256;

struct PcdField {
  std::string name;
  long long size = 0, count = 1;
  char type = '?';
};

struct PcdHeader {
  long long width = -1, height = -1;
  std::size_t point_size = 0;
  std::string data;
  std::size_t data_offset = 0;  ///< where the body starts
  int data_line = 0;            ///< the DATA line's number
  std::vector<PcdField> fields;
  const PcdField* find(const std::string& name) const {
    for (const auto& f : fields)
      if (f.name == name) return &f;
    return nullptr;
  }
};

// One whole-number header value in [lo, hi], or an InputError naming the file, line, key and value.
long long header_int(const std::string& token, long long lo, long long hi, const std::string& where,
                     const std::string& expected) {
  long long v = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size() || v < lo || v > hi)
    throw InputError(where + printable(token) + ": expected " + expected);
  return v;
}

// Reads and checks the header and the body's size before PCL sees the file, so that a
// truncated, corrupt or absurd file is one clear error and never a read past the end or an
// allocation of the size a corrupt header claims.
PcdHeader check_pcd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  PcdHeader h;
  std::vector<std::string> sizes, counts, types;
  long long points = -1;
  std::string line;
  int lineno = 0;
  bool have_data = false;
  while (!have_data && std::getline(in, line)) {
    ++lineno;
    if (lineno > 64 || line.size() > 4096)
      throw InputError(path + ": not a PCD file (no DATA line in the first 64 lines)");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::string where = path + ": line " + std::to_string(lineno) + ": ";
    std::istringstream s(line);
    std::string key, token;
    s >> key;
    std::vector<std::string> values;
    while (s >> token) values.push_back(token);
    auto one = [&]() -> const std::string& {
      if (values.size() != 1) throw InputError(where + key + " needs one value, got " + std::to_string(values.size()));
      return values[0];
    };
    if (key == "FIELDS") {
      if (values.empty() || values.size() > kMaxFields)
        throw InputError(where + "FIELDS needs 1 to " + std::to_string(kMaxFields) + " names");
      for (const auto& f : values) h.fields.push_back({f});
    } else if (key == "SIZE") {
      sizes = values;
    } else if (key == "COUNT") {
      counts = values;
    } else if (key == "TYPE") {
      types = values;
    } else if (key == "WIDTH") {
      h.width = header_int(one(), 1, kMaxSide, where + "WIDTH ", "a whole number from 1 to " + std::to_string(kMaxSide));
    } else if (key == "HEIGHT") {
      h.height = header_int(one(), 1, kMaxSide, where + "HEIGHT ", "a whole number from 1 to " + std::to_string(kMaxSide));
    } else if (key == "POINTS") {
      points = header_int(one(), 0, kMaxSide * kMaxSide, where + "POINTS ", "a whole number (WIDTH times HEIGHT)");
    } else if (key == "DATA") {
      h.data = one();
      h.data_line = lineno;
      if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed")
        throw InputError(where + "DATA " + printable(h.data) + ": expected ascii, binary or binary_compressed");
      have_data = true;
    } else if (key != "VERSION" && key != "VIEWPOINT") {
      throw InputError(path + ": not a PCD file (line " + std::to_string(lineno) + ": " + printable(line) +
                       " is not a header line, and no DATA line came before it)");
    }
  }
  if (!have_data) throw InputError(path + ": not a PCD file (no DATA line in the header)");
  if (h.fields.empty()) throw InputError(path + ": corrupt PCD header (no FIELDS line)");
  if (h.width < 0 || h.height < 0) throw InputError(path + ": corrupt PCD header (no WIDTH or HEIGHT line)");
  const std::size_t nf = h.fields.size();
  if (sizes.size() != nf || (!types.empty() && types.size() != nf) || (!counts.empty() && counts.size() != nf))
    throw InputError(path + ": corrupt PCD header (" + std::to_string(nf) + " FIELDS but " +
                     std::to_string(sizes.size()) + " SIZE, " + std::to_string(types.size()) + " TYPE and " +
                     std::to_string(counts.size()) + " COUNT values)");
  for (std::size_t i = 0; i < nf; ++i) {
    PcdField& f = h.fields[i];
    const std::string where = path + ": field " + printable(f.name) + " ";
    f.size = header_int(sizes[i], 1, 8, where + "SIZE ", "1, 2, 4 or 8");
    if (f.size == 3 || (f.size > 4 && f.size < 8)) throw InputError(where + "SIZE " + sizes[i] + ": expected 1, 2, 4 or 8");
    if (!counts.empty()) f.count = header_int(counts[i], 1, kMaxCount, where + "COUNT ", "1 to " + std::to_string(kMaxCount));
    f.type = types.empty() ? 'F' : types[i].size() == 1 ? types[i][0] : '?';
    if (f.type != 'F' && f.type != 'U' && f.type != 'I')
      throw InputError(where + "TYPE " + printable(types[i]) + ": expected F, U or I");
    if (f.type == 'F' && f.size != 4 && f.size != 8)
      throw InputError(where + "is a float (TYPE F) of SIZE " + sizes[i] + ": expected 4 or 8");
    h.point_size += std::size_t(f.size * f.count);
  }
  for (const char* name : {"x", "y", "z"}) {
    const PcdField* f = h.find(name);
    if (!f) throw InputError(path + ": the PCD file has no x, y, z fields");
    if (f->type != 'F' || f->size != 4 || f->count != 1)
      throw InputError(path + ": field " + name + " is not one FLOAT32 (SIZE 4, TYPE F, COUNT 1)");
  }
  for (const char* name : {"rgb", "rgba"})
    if (const PcdField* f = h.find(name); f && (f->size != 4 || f->count != 1))
      throw InputError(path + ": field " + name + " has SIZE " + std::to_string(f->size) + " COUNT " +
                       std::to_string(f->count) + ": a packed colour is SIZE 4, COUNT 1");
  const std::size_t n = std::size_t(h.width) * std::size_t(h.height);
  if (n > std::size_t(kMaxPoints))
    throw InputError(path + ": WIDTH " + std::to_string(h.width) + " x HEIGHT " + std::to_string(h.height) +
                     " is more than " + std::to_string(kMaxPoints) + " points");
  if (n * h.point_size > (std::size_t(1) << 31))
    throw InputError(path + ": " + std::to_string(n) + " points of " + std::to_string(h.point_size) +
                     " bytes each are more than 2 GiB");
  if (points >= 0 && std::size_t(points) != n)
    throw InputError(path + ": corrupt PCD header (POINTS " + std::to_string(points) + " but WIDTH x HEIGHT = " +
                     std::to_string(n) + ")");
  const std::size_t data_offset = h.data_offset = static_cast<std::size_t>(in.tellg());
  in.seekg(0, std::ios::end);
  const std::size_t file_size = static_cast<std::size_t>(in.tellg());
  const std::size_t body = file_size - data_offset;
  if (h.data == "binary") {
    if (body < n * h.point_size)
      throw InputError(path + ": truncated PCD file (" + std::to_string(body) + " bytes of data, " +
                       std::to_string(n * h.point_size) + " expected)");
  } else if (h.data == "binary_compressed") {
    std::uint32_t sz[2] = {0, 0};
    in.seekg(static_cast<std::streamoff>(data_offset));
    if (body < 8 || !in.read(reinterpret_cast<char*>(sz), 8))
      throw InputError(path + ": truncated PCD file (no compressed data)");
    if (sz[0] > body - 8)
      throw InputError(path + ": truncated PCD file (" + std::to_string(body - 8) +
                       " bytes of compressed data, " + std::to_string(sz[0]) + " expected)");
    if (sz[1] != n * h.point_size)
      throw InputError(path + ": corrupt PCD file (uncompressed size " + std::to_string(sz[1]) +
                       ", " + std::to_string(n * h.point_size) + " expected)");
  } else {  // ascii: every value takes at least one character and a separator
    std::size_t values = 0;
    for (const auto& f : h.fields) values += std::size_t(f.count);
    if (body + 1 < n * values * 2)
      throw InputError(path + ": truncated PCD file (" + std::to_string(body) + " bytes of text for " +
                       std::to_string(n) + " points of " + std::to_string(values) + " values)");
  }
  return h;
}

const pcl::PCLPointField* field(const pcl::PCLPointCloud2& c, const std::string& name) {
  for (const auto& f : c.fields)
    if (f.name == name) return &f;
  return nullptr;
}

// The PCL field type of a header field (pcl::PCLPointField's datatype codes).
std::uint8_t pcl_type(const PcdField& f) {
  using P = pcl::PCLPointField;
  if (f.type == 'F') return f.size == 4 ? P::FLOAT32 : P::FLOAT64;
  const bool u = f.type == 'U';
  switch (f.size) {
    case 1: return u ? P::UINT8 : P::INT8;
    case 2: return u ? P::UINT16 : P::INT16;
    case 4: return u ? P::UINT32 : P::INT32;
    default: return u ? P::UINT64 : P::INT64;
  }
}

// The points of a checked header as PCL lays them out: the fields packed in order, one point
// after another (the data zeroed, to be filled by a body reader).
pcl::PCLPointCloud2 layout(const PcdHeader& h) {
  pcl::PCLPointCloud2 blob;
  blob.width = std::uint32_t(h.width), blob.height = std::uint32_t(h.height);
  for (const auto& f : h.fields) {
    pcl::PCLPointField pf;
    pf.name = f.name;
    pf.offset = std::uint32_t(blob.point_step);
    pf.datatype = pcl_type(f);
    pf.count = std::uint32_t(f.count);
    blob.fields.push_back(pf);
    blob.point_step += std::uint32_t(f.size * f.count);
  }
  blob.row_step = blob.point_step * blob.width;
  blob.data.resize(std::size_t(blob.row_step) * blob.height);
  return blob;
}

// Binary and binary_compressed bodies, read here rather than by PCL (the fuzzer made PCL's reader
// allocate what a corrupt file claims): the sizes are checked in check_pcd, the compressed data
// go through PCL's bounds-checked LZF decoder, whose output holds each field for every point in
// turn.
pcl::PCLPointCloud2 read_binary(const std::string& path, const PcdHeader& h) {
  pcl::PCLPointCloud2 blob = layout(h);
  const std::size_t n = std::size_t(h.width) * std::size_t(h.height);
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(h.data_offset));
  if (h.data == "binary") {
    if (!in.read(reinterpret_cast<char*>(blob.data.data()), std::streamsize(blob.data.size())))
      throw InputError(path + ": truncated PCD file (the data end early)");
    return blob;
  }
  std::uint32_t sz[2];
  in.read(reinterpret_cast<char*>(sz), 8);
  std::vector<char> packed(sz[0]);
  if (!in.read(packed.data(), std::streamsize(sz[0]))) throw InputError(path + ": truncated PCD file (compressed data)");
  std::vector<std::uint8_t> fields(sz[1]);  // == n * point_step, checked in check_pcd
  if (sz[1] > 0 && pcl::lzfDecompress(packed.data(), sz[0], fields.data(), sz[1]) != sz[1])
    throw InputError(path + ": corrupt PCD file (the compressed data do not decompress to " + std::to_string(sz[1]) +
                     " bytes)");
  const std::uint8_t* src = fields.data();
  for (std::size_t k = 0; k < h.fields.size(); ++k) {
    const std::size_t bytes = std::size_t(h.fields[k].size * h.fields[k].count), offset = blob.fields[k].offset;
    for (std::size_t i = 0; i < n; ++i, src += bytes) std::memcpy(blob.data.data() + i * blob.point_step + offset, src, bytes);
  }
  return blob;
}

// An ascii body, read here rather than by PCL (whose ascii reader crashed on malformed lines):
// one point per line, each value parsed as its field's type; any other line is an error that
// names it.
pcl::PCLPointCloud2 read_ascii(const std::string& path, const PcdHeader& h) {
  pcl::PCLPointCloud2 blob = layout(h);
  std::size_t values = 0;
  for (const auto& f : h.fields) values += std::size_t(f.count);
  const std::size_t n = std::size_t(h.width) * std::size_t(h.height);
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(h.data_offset));
  std::string line;
  int lineno = h.data_line;
  std::size_t i = 0;
  while (i < n && std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const char* c = line.c_str();
    std::uint8_t* out = blob.data.data() + i * blob.point_step;
    std::size_t k = 0;
    for (const auto& f : h.fields)
      for (long long j = 0; j < f.count; ++j, ++k) {
        while (*c == ' ' || *c == '\t') ++c;
        char* end = nullptr;
        errno = 0;
        if (f.type == 'F') {
          const double x = std::strtod(c, &end);
          if (f.size == 4) {
            const float y = float(x);
            std::memcpy(out, &y, 4);
          } else {
            std::memcpy(out, &x, 8);
          }
        } else if (f.type == 'U') {
          const unsigned long long x = *c == '-' ? 0 : std::strtoull(c, &end, 10);
          std::memcpy(out, &x, std::size_t(f.size));  // little-endian: the low bytes
          if (*c == '-' || (f.size < 8 && x >> (8 * f.size))) end = nullptr;
        } else {
          const long long x = std::strtoll(c, &end, 10);
          std::memcpy(out, &x, std::size_t(f.size));
          if (f.size < 8 && (x < -(1LL << (8 * f.size - 1)) || x >= (1LL << (8 * f.size - 1)))) end = nullptr;
        }
        if (!end || end == c || (*end && *end != ' ' && *end != '\t') || (f.type != 'F' && errno == ERANGE))
          throw InputError(path + ": line " + std::to_string(lineno) + ": value " + std::to_string(k + 1) + " (" +
                           printable(f.name) + ") is not a " + (f.type == 'F' ? "number" : "whole number") +
                           " of " + std::to_string(f.size) + " bytes: " + printable(line));
        c = end;
        out += f.size;
      }
    while (*c == ' ' || *c == '\t') ++c;
    if (*c) throw InputError(path + ": line " + std::to_string(lineno) + ": more than the " + std::to_string(values) +
                             " values of a point: " + printable(line));
    ++i;
  }
  if (i < n)
    throw InputError(path + ": truncated PCD file (" + std::to_string(i) + " of " + std::to_string(n) +
                     " points in the ascii data)");
  return blob;
}

}  // namespace

Frame read_pcd(const std::string& path, const ReadOptions& options) {
  require_file(path);
  const PcdHeader header = check_pcd(path);
  if (header.height == 1)
    throw InputError(path + ": the PCD file is not organized (HEIGHT 1, WIDTH " +
                     std::to_string(header.width) + "); an image-shaped cloud is needed");
  const pcl::PCLPointCloud2 blob = header.data == "ascii" ? read_ascii(path, header) : read_binary(path, header);
  const auto *fx = field(blob, "x"), *fy = field(blob, "y"), *fz = field(blob, "z");  // FLOAT32 (check_pcd)
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
      if (valid_point(xyz)) {
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
    std::size_t valid = 0;
    for (std::size_t i = 0; i < frame.depth.pixels() && valid < 10; ++i) valid += frame.depth.data()[i] > 0.f;
    if (valid < 10) {  // nothing measured (all NaN or out of range): a frame that yields an empty result
      frame.intrinsics = {525.0 * cols / 640.0, 525.0 * cols / 640.0, (cols - 1) / 2.0, (rows - 1) / 2.0};
    } else {
      try {
        frame.intrinsics = extension::fit_intrinsics(frame.cloud);
      } catch (const InputError& e) {
        throw InputError(path + ": " + e.what());
      }
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
