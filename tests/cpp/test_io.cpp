// Frame I/O: readers, writers and their errors on bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "mereo/core/error.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/io/io.hpp"
#include "mereo/signal/depth_filter.hpp"

namespace fs = std::filesystem;
using mereo::InputError;

namespace {

const std::string kReal = MEREO_REAL_DATA;

fs::path scratch(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("mereo_test_io_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

// A small frame with known values: a tilted plane and a colour gradient.
mereo::Frame make_frame(int rows = 48, int cols = 64) {
  mereo::Frame f;
  f.id = "t";
  f.source = "test";
  f.intrinsics = {60.0, 61.0, 31.5, 23.5};
  f.depth = mereo::DepthImage(rows, cols);
  f.color = mereo::ColorImage(rows, cols);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) {
      f.depth(v, u) = (u == 3 && v == 5) ? mereo::kNaN : 0.8f + 0.004f * u + 0.002f * v;
      f.color(v, u, 0) = std::uint8_t(u * 3), f.color(v, u, 1) = std::uint8_t(v * 5), f.color(v, u, 2) = 77;
    }
  return f;
}

// Expects `fn` to throw InputError whose message contains every string in `parts`.
template <typename Fn>
void expect_error(Fn fn, std::initializer_list<std::string> parts) {
  try {
    fn();
    FAIL() << "no error thrown";
  } catch (const InputError& e) {
    for (const auto& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(Intrinsics, ParseAndReject) {
  const auto K = mereo::Intrinsics::parse("525,526.5, 319.5,239.5");
  EXPECT_DOUBLE_EQ(K.fy, 526.5);
  EXPECT_DOUBLE_EQ(K.cx, 319.5);
  expect_error([] { mereo::Intrinsics::parse("525,525,319.5"); }, {"expected 4 numbers"});
  expect_error([] { mereo::Intrinsics::parse("525,abc,319.5,239.5"); }, {"'abc' is not a number"});
  expect_error([] { mereo::Intrinsics::parse("-1,525,319.5,239.5"); }, {"fx -1 is not a focal length"});
}

TEST(Projection, BackProjectAndFitIntrinsicsRoundTrip) {
  const auto f = make_frame();
  const auto cloud = mereo::extension::back_project(f);
  EXPECT_TRUE(std::isnan(cloud(5, 3, 0)));
  const float z = f.depth(10, 20);
  EXPECT_NEAR(cloud(10, 20, 0), (20 - 31.5) * z / 60.0, 1e-6);
  EXPECT_NEAR(cloud(10, 20, 1), (10 - 23.5) * z / 61.0, 1e-6);
  double residual = 1;
  const auto K = mereo::extension::fit_intrinsics(cloud, &residual);
  EXPECT_NEAR(K.fx, 60.0, 1e-3);
  EXPECT_NEAR(K.fy, 61.0, 1e-3);
  EXPECT_NEAR(K.cx, 31.5, 1e-3);
  EXPECT_NEAR(K.cy, 23.5, 1e-3);
  EXPECT_LT(residual, 1e-3);
}

TEST(PngPair, WriteReadRoundTrip) {
  const auto dir = scratch("png");
  const auto f = make_frame();
  const auto paths = mereo::io::write_png_pair(dir.string(), "0001", f, 5000.0);
  ASSERT_EQ(paths.size(), 2u);
  // The folder reader finds the pair and intrinsics.json (with its depth scale).
  const auto g = mereo::io::read(dir.string());
  EXPECT_EQ(g.id, "0001");
  EXPECT_EQ(g.intrinsics, f.intrinsics);
  ASSERT_TRUE(g.depth.same_size(f.depth));
  EXPECT_TRUE(std::isnan(g.depth(5, 3)));
  for (int v = 0; v < f.rows(); v += 7)
    for (int u = 0; u < f.cols(); u += 5) {
      if (u == 3 && v == 5) continue;
      EXPECT_NEAR(g.depth(v, u), f.depth(v, u), 0.5 / 5000 + 1e-6);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(g.color(v, u, c), f.color(v, u, c));
    }
  // The depth file alone finds its colour partner.
  const auto h = mereo::io::read((dir / "0001_depth.png").string());
  EXPECT_EQ(h.color(3, 4, 0), f.color(3, 4, 0));
}

TEST(PngPair, ClearErrors) {
  const auto dir = scratch("png_bad");
  const auto f = make_frame();
  mereo::io::write_png_pair(dir.string(), "a", f);
  auto small = make_frame(24, 32);
  mereo::io::write_png_pair((dir / "small").string(), "a", small);
  // Colour and depth of different sizes.
  fs::copy_file(dir / "small" / "a_depth.png", dir / "a_depth.png", fs::copy_options::overwrite_existing);
  expect_error([&] { mereo::io::read((dir / "a_depth.png").string()); }, {"a_depth.png", "32x24", "64x48"});
  // A corrupt PNG.
  std::ofstream((dir / "a_depth.png").string(), std::ios::binary) << "\x89PNG\r\n\x1a\nthis is not a png";
  expect_error([&] { mereo::io::read((dir / "a_depth.png").string()); }, {"a_depth.png", "cannot decode"});
  // A file of another format: OpenCV's DICOM decoder (GDCM) aborted the process on this header
  // (the fuzzer's), so only PNG, PNM, JPEG, TIFF and OpenEXR files reach OpenCV
  std::ofstream((dir / "a_depth.png").string(), std::ios::binary)
      << std::string(128, '\xff') << "DICM" << std::string(16, '\xff');
  expect_error([&] { mereo::io::read((dir / "a_depth.png").string()); },
               {"a_depth.png", "not a PNG, PNM, JPEG, TIFF or OpenEXR image"});
  // A missing file; a pair with no intrinsics anywhere.
  expect_error([&] { mereo::io::read((dir / "nothing_depth.png").string()); }, {"nothing_depth.png", "no such"});
  const auto lone = scratch("png_noK");
  fs::copy_file(dir / "small" / "a_rgb.png", lone / "b_rgb.png");
  fs::copy_file(dir / "small" / "a_depth.png", lone / "b_depth.png");
  expect_error([&] { mereo::io::read(lone.string()); }, {"no intrinsics"});
  // Given intrinsics, the same folder reads.
  mereo::io::ReadOptions o;
  o.intrinsics = mereo::Intrinsics{30, 30, 16, 12};
  EXPECT_EQ(mereo::io::read(lone.string(), o).cols(), 32);
  // an image whose header claims more than 2^25 pixels (OpenCV allocated 2.3 GB for the fuzzer's
  // PPM before decoding), and a PNM header that is not two numbers
  std::ofstream((lone / "b_rgb.ppm").string(), std::ios::binary) << "P6\n100000 100000\n255\n" << std::string(64, 'x');
  fs::remove(lone / "b_rgb.png");
  expect_error([&] { mereo::io::read(lone.string(), o); }, {"b_rgb.ppm: the image's header says 100000x100000 pixels"});
  std::ofstream((lone / "b_rgb.ppm").string(), std::ios::binary) << "P6\n8888z88831 1\n255\n";
  expect_error([&] { mereo::io::read(lone.string(), o); }, {"b_rgb.ppm: cannot decode the image (corrupt header)"});
  fs::copy_file(dir / "small" / "a_rgb.png", lone / "b_rgb.png");
  fs::remove(lone / "b_rgb.ppm");
  // A bad intrinsics file names the field.
  std::ofstream((lone / "intrinsics.json").string()) << R"({"fx": 30, "fy": "thirty", "cx": 16, "cy": 12})";
  expect_error([&] { mereo::io::read(lone.string()); }, {"intrinsics.json", "'fy'"});
  // a number beyond a double (nlohmann's out_of_range escaped, found by the fuzzer)
  std::ofstream((lone / "intrinsics.json").string()) << R"({"fx": 8.0E0077735347949794, "fy": 30, "cx": 16, "cy": 12})";
  expect_error([&] { mereo::io::read(lone.string()); }, {"intrinsics.json: not valid JSON (a number out of range)"});
}

TEST(Pcd, WriteReadRoundTripWithLabels) {
  const auto dir = scratch("pcd");
  auto f = make_frame();
  f.labels = mereo::LabelImage(f.rows(), f.cols(), 0);
  f.labels(7, 9) = 42;
  const std::string path = (dir / "x.pcd").string();
  mereo::io::write_pcd(path, f);
  const auto g = mereo::io::read(path);
  EXPECT_EQ(g.id, "x");
  ASSERT_TRUE(g.cloud.same_size(f.depth));
  EXPECT_EQ(g.labels(7, 9), 42u);
  EXPECT_TRUE(std::isnan(g.depth(5, 3)));
  EXPECT_FLOAT_EQ(g.depth(20, 30), f.depth(20, 30));
  EXPECT_EQ(g.color(20, 30, 1), f.color(20, 30, 1));
  EXPECT_NEAR(g.intrinsics.fx, 60.0, 1e-2);  // fitted to the cloud
}

TEST(Pcd, ClearErrors) {
  const auto dir = scratch("pcd_bad");
  expect_error([&] { mereo::io::read((dir / "missing.pcd").string()); }, {"missing.pcd", "no such"});
  std::ofstream((dir / "garbage.pcd").string()) << "hello world\n";
  expect_error([&] { mereo::io::read((dir / "garbage.pcd").string()); }, {"garbage.pcd", "not a PCD"});
  // Truncate a valid binary_compressed file.
  const auto f = make_frame();
  const std::string good = (dir / "good.pcd").string();
  mereo::io::write_pcd(good, f);
  const auto size = fs::file_size(good);
  fs::copy_file(good, dir / "cut.pcd");
  fs::resize_file(dir / "cut.pcd", size / 2);
  expect_error([&] { mereo::io::read((dir / "cut.pcd").string()); }, {"cut.pcd", "truncated"});
  // An unorganized cloud.
  std::ofstream((dir / "flat.pcd").string())
      << "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
         "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n0 0 1\n0.1 0 1\n";
  expect_error([&] { mereo::io::read((dir / "flat.pcd").string()); }, {"flat.pcd", "not organized"});
}

// The headers that crashed or misled (issue 19), each one named error; ascii and binary alike.
TEST(Pcd, HeaderValuesAreRangeChecked) {
  const auto dir = scratch("pcd_header");
  auto write = [&](const std::string& name, const std::string& fields) {
    const std::string path = (dir / name).string();
    std::ofstream out(path, std::ios::binary);
    out << "VERSION .7\n" << fields << "VIEWPOINT 0 0 0 1 0 0 0\n";
    if (fields.find("DATA") == std::string::npos) out << "DATA binary\n";
    for (int i = 0; i < 4 * 4 * 6; ++i) out.put(char(i % 7));  // 6 points of 4 floats, any values
    return path;
  };
  const std::string dims = "WIDTH 3\nHEIGHT 2\nPOINTS 6\n";
  const std::string xyzrgb = "FIELDS x y z rgb\nTYPE F F F U\n";
  expect_error([&] { mereo::io::read(write("count.pcd", xyzrgb + "SIZE 4 4 4 4\nCOUNT -1 1 1 1\n" + dims)); },
               {"count.pcd", "field 'x' COUNT '-1': expected 1 to 4096"});
  expect_error([&] { mereo::io::read(write("size.pcd", xyzrgb + "SIZE -4 4 4 4\nCOUNT 1 1 1 1\n" + dims)); },
               {"size.pcd", "field 'x' SIZE '-4'"});
  expect_error([&] { mereo::io::read(write("rgb1.pcd", xyzrgb + "SIZE 4 4 4 1\n" + dims)); },
               {"rgb1.pcd", "field rgb has SIZE 1"});
  expect_error([&] { mereo::io::read(write("x8.pcd", xyzrgb + "SIZE 8 4 4 4\n" + dims)); },
               {"x8.pcd", "field x is not one FLOAT32"});
  expect_error([&] { mereo::io::read(write("huge.pcd", xyzrgb + "SIZE 4 4 4 4\nWIDTH 100000\nHEIGHT 100000\n")); },
               {"huge.pcd", "WIDTH '100000'"});
  expect_error([&] { mereo::io::read(write("big.pcd", xyzrgb + "SIZE 4 4 4 4\nWIDTH 65536\nHEIGHT 65536\n")); },
               {"big.pcd", "more than 33554432 points"});
  expect_error([&] { mereo::io::read(write("points.pcd", xyzrgb + "SIZE 4 4 4 4\nWIDTH 3\nHEIGHT 2\nPOINTS 7\n")); },
               {"points.pcd", "POINTS 7 but WIDTH x HEIGHT = 6"});
  expect_error([&] { mereo::io::read(write("ascii.pcd", xyzrgb + "SIZE 4 4 4 4\nWIDTH 300\nHEIGHT 200\nDATA ascii\n")); },
               {"ascii.pcd", "truncated PCD file"});
  expect_error([&] { mereo::io::read(write("type.pcd", "FIELDS x y z rgb\nTYPE F F F Q\nSIZE 4 4 4 4\n" + dims)); },
               {"type.pcd", "TYPE 'Q': expected F, U or I"});
  // text that is not UTF-8 is quoted with \x escapes, so the message stays one valid line
  expect_error([&] { mereo::io::read(write("latin.pcd", "FOO\xe9 1\n" + xyzrgb)); },
               {"latin.pcd", "line 2: 'FOO\\xe9 1' is not a header line"});
}

// Valid but extreme data: coordinates of 1e30 (and the inf they overflow to) are out of any
// sensor's range and count as missing; the rest of the frame is read, filtered and projected.
TEST(Pcd, CoordinatesOutOfRangeAreMissing) {
  const auto dir = scratch("pcd_extreme");
  const std::string path = (dir / "e.pcd").string();
  {
    std::ofstream out(path, std::ios::binary);
    out << "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 16\nHEIGHT 12\nPOINTS 192\nDATA binary\n";
    for (int v = 0; v < 12; ++v)
      for (int u = 0; u < 16; ++u) {
        const float s = v < 3 ? 1e30f : v == 3 ? 1e-40f : 1.f;  // rows 0-2 huge, row 3 denormal
        const float p[3] = {s * (u - 7.5f) * 0.01f, s * (v - 5.5f) * 0.01f, s * 1.f};
        out.write(reinterpret_cast<const char*>(p), sizeof p);
      }
  }
  const auto f = mereo::io::read(path);
  EXPECT_TRUE(std::isnan(f.depth(0, 5)) && std::isnan(f.depth(2, 5)) && std::isnan(f.depth(3, 5)));
  EXPECT_FLOAT_EQ(f.depth(4, 5), 1.f);
  EXPECT_NEAR(f.intrinsics.fx, 100.0, 1e-3);  // fitted to the valid rows only
  // an all-extreme depth image through the filter: NaN out, no crash (it indexed a table with NaN)
  mereo::DepthImage d(8, 8, 1e30f);
  d(0, 0) = std::numeric_limits<float>::infinity();
  d(1, 1) = 1e-40f;
  const auto out = mereo::signal::filter_depth(d, {});
  for (std::size_t i = 0; i < out.pixels(); ++i) EXPECT_TRUE(std::isnan(out.data()[i]));
}

TEST(PngPair, DepthMustBeOneChannelOf16BitOrFloatAndScalesFinite) {
  const auto dir = scratch("png_depth_kind");
  const auto f = make_frame();
  mereo::io::write_png_pair(dir.string(), "a", f);
  const std::string depth = (dir / "a_depth.png").string(), color = (dir / "a_rgb.png").string();
  fs::copy_file(color, dir / "b_rgb.png");
  fs::copy_file(color, dir / "b_depth.png");  // a colour image as depth
  expect_error([&] { mereo::io::read((dir / "b_depth.png").string()); },
               {"b_depth.png", "one channel of 16-bit units or 32-bit float metres", "3 channel(s) of 8-bit"});
  for (const double scale : {0.0, -1000.0, std::nan(""), HUGE_VAL})
    expect_error([&] { mereo::io::read_png_pair(color, depth, f.intrinsics, scale); },
                 {"a_depth.png", "is not a finite positive number of depth units per metre"});
  mereo::io::ReadOptions o;
  o.depth_scale = -1;
  expect_error([&] { mereo::io::open({depth}, o); }, {"--depth-scale", "depth scale -1 is not"});
  std::ofstream((dir / "intrinsics.json").string()) << R"({"fx": 60, "fy": 61, "cx": 31.5, "cy": 23.5, "depth_scale": 0})";
  expect_error([&] { mereo::io::read(depth); }, {"intrinsics.json: field 'depth_scale': depth scale 0 is not"});
  // a tiny scale puts every depth beyond any sensor's range: read, all missing
  const auto far = mereo::io::read_png_pair(color, depth, f.intrinsics, 1e-30);
  for (std::size_t i = 0; i < far.depth.pixels(); ++i) EXPECT_TRUE(std::isnan(far.depth.data()[i]));
}

TEST(Intrinsics, FocalLengthsAndPrincipalPointInRange) {
  expect_error([] { mereo::Intrinsics::parse("1e300,1e300,319.5,239.5"); },
               {"fx 1e+300 is not a focal length in pixels (expected 0 < fx <= 100000)"});
  expect_error([] { mereo::Intrinsics::parse("525,-1,319.5,239.5"); }, {"fy -1 is not a focal length"});
  auto f = make_frame();
  f.intrinsics.cx = 5000;
  expect_error([&] { f.validate(); }, {"the principal point (5000, 23.5) is outside the 64x48 image"});
}

TEST(Pcd, RealMugScene) {
  const std::string path = kReal + "/pcl/table_scene_mug_stereo_textured.pcd";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  const auto f = mereo::io::read(path);
  EXPECT_EQ(f.cols(), 640);
  EXPECT_EQ(f.rows(), 480);
  std::size_t nan = 0;
  for (std::size_t i = 0; i < f.depth.pixels(); ++i) nan += std::isnan(f.depth.data()[i]);
  EXPECT_EQ(nan, 97920u);  // as PCL's documentation says of this file
  EXPECT_NEAR(f.intrinsics.fx, 964.36, 0.05);
  EXPECT_NEAR(f.intrinsics.cy, 223.36, 0.05);
}

TEST(Pcd, RealMosdLabels) {
  const std::string path = kReal + "/pcl-mosd/test34.pcd";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  const auto f = mereo::io::read(path);
  ASSERT_FALSE(f.labels.empty());
  // Label 0 occurs exactly on the missing points (SOURCE.md).
  std::size_t mismatch = 0;
  for (std::size_t i = 0; i < f.depth.pixels(); ++i)
    mismatch += (f.labels.data()[i] == 0) != std::isnan(f.depth.data()[i]);
  EXPECT_EQ(mismatch, 0u);
  EXPECT_NEAR(f.intrinsics.fx, 525.0, 0.01);
}

TEST(RealImages, PosecnnPairWithGivenCamera) {
  const std::string path = kReal + "/posecnn/000002-depth.png";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  mereo::io::ReadOptions o;
  o.intrinsics = mereo::Intrinsics{1066.778, 1067.487, 312.9869, 241.3109};
  o.depth_scale = 10000;
  const auto f = mereo::io::read(path, o);
  std::vector<float> z;
  for (std::size_t i = 0; i < f.depth.pixels(); ++i)
    if (std::isfinite(f.depth.data()[i])) z.push_back(f.depth.data()[i]);
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  EXPECT_NEAR(z[z.size() / 2], 0.972, 0.01);  // SOURCE.md: median 0.972 m
  EXPECT_NEAR(double(z.size()) / f.depth.pixels(), 0.714, 0.01);
}

TEST(Tum, AssociatesByTimestampWithPoses) {
  const auto dir = scratch("tum");
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  const auto f = make_frame();
  // Write frames with the PNG writer, then arrange them as TUM does (depth scale 5000).
  mereo::io::write_png_pair((dir / "tmp").string(), "a", f, 5000.0);
  for (const char* t : {"1.000000", "1.033000", "1.066000"}) {
    fs::copy_file(dir / "tmp" / "a_rgb.png", dir / "rgb" / (std::string(t) + ".png"));
    fs::copy_file(dir / "tmp" / "a_depth.png", dir / "depth" / (std::string(t) + ".png"));
  }
  std::ofstream(dir / "rgb.txt") << "# color images\n1.005 rgb/1.000000.png\n1.035 rgb/1.033000.png\n1.2 rgb/1.066000.png\n";
  std::ofstream(dir / "depth.txt") << "# depth\n1.000 depth/1.000000.png\n1.033 depth/1.033000.png\n1.066 depth/1.066000.png\n";
  std::ofstream(dir / "groundtruth.txt") << "# tx ty tz qx qy qz qw\n1.001 1 2 3 0 0 0 1\n1.034 1 2 4 0 0 0.7071068 0.7071068\n";
  mereo::io::ReadOptions o;
  o.intrinsics = f.intrinsics;
  const auto seq = mereo::io::open({dir.string()}, o);
  ASSERT_EQ(seq.size(), 2u);  // the third depth has no colour within 0.02 s
  const auto g = seq.load(1);
  EXPECT_EQ(g.id, "1.033000");
  EXPECT_DOUBLE_EQ(g.timestamp, 1.033);
  ASSERT_TRUE(g.pose.has_value());
  EXPECT_NEAR(g.pose->translation().z(), 4.0, 1e-12);
  EXPECT_NEAR(g.depth(10, 20), f.depth(10, 20), 0.5 / 5000 + 1e-6);
  // a pose line with a value missing: the file and its line
  std::ofstream(dir / "groundtruth.txt") << "# tx ty tz qx qy qz qw\n1.001 1 2 3 0 0 0 1\n1.034 1 2 4 0 0 0.7071068\n";
  expect_error([&] { mereo::io::open({dir.string()}, o); }, {"groundtruth.txt:3", "qw"});
  // a zero quaternion was read as the identity
  std::ofstream(dir / "groundtruth.txt") << "# tx ty tz qx qy qz qw\n1.001 1 2 3 0 0 0 0\n";
  expect_error([&] { mereo::io::open({dir.string()}, o); },
               {"groundtruth.txt:2: the quaternion 0 0 0 0 has norm 0 (expected a unit quaternion"});
}

TEST(Open, UnknownInputsAreClearErrors) {
  expect_error([] { mereo::io::read("synthetic:abc"); }, {"synthetic:abc", "SEED"});
  expect_error([] { mereo::io::read("/nonexistent/folder/x.pcd"); }, {"x.pcd", "no such"});
  const auto dir = scratch("empty");
  expect_error([&] { mereo::io::read(dir.string()); }, {"no frames found"});
  std::ofstream((dir / "notes.txt").string()) << "x";
  expect_error([&] { mereo::io::read((dir / "notes.txt").string()); }, {"notes.txt", "unknown input"});
}
