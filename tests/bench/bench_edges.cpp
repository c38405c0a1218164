// bench_edges: the edge modality's lines and arcs (features::detect_edge_primitives, on its
// default chains, Canny's linked; the same with the fixed threshold, not raised on textured
// images; and on Edge Drawing's chains) against OpenCV's own detectors on the same colour images, in one process:
// Canny's edge pixels, the Fast Line Detector (ximgproc), the line segment detector (LSD), and
// Edge Drawing's own lines and ellipses (ximgproc).
//
// Per method: median ms per frame, and recall of the objects' outlines (eval_edges.hpp: outline
// pixels the colour shows, reached within 2 pixels by the method's pixels; lines and ellipses
// are drawn one pixel wide). Outlines come from the renderer's object labels (both depth models;
// the colour is the same) and from the masks of ../shared/data/real/nv-6dof-graspnet (real
// RealSense-like frames; the masks are the objects' projected points, closed by 5 pixels).
// mereo also reports arcs on mug handles: of the rendered handles showing at least 150 pixels,
// the share with an arc whose pixels lie mostly (>= 50%) within 2 pixels of the handle.
// Methods are interleaved per frame so that machine load affects them alike. Then the
// registration of depth from a second camera (signal::register_depth) against OpenCV's
// rgbd::registerDepth on the same depth images. The last line is one JSON object.
//
//   bench_edges            the full run (24 rendered scenes, seeds 9300-9311 Kinect-like and
//                          9400-9411 stereo; 5 real frames; 3 repetitions)
//   bench_edges --quick    a few frames (ctest)
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd.hpp>
#include <opencv2/ximgproc.hpp>

#include "mereo/extension/projection.hpp"
#include "mereo/features/edges.hpp"
#include "mereo/io/io.hpp"
#include "mereo/signal/register.hpp"
#include "mereo/synthetic/scene.hpp"
#include "bench_util.hpp"
#include "eval_edges.hpp"

namespace fs = std::filesystem;
using namespace mereo;
using bench::median;
using bench::now_ms;

namespace {

struct Input {
  std::string name;
  bool synthetic = false;
  Frame frame;
  Cloud cloud;
  cv::Mat grey;
  std::vector<int> outline;
  std::vector<std::vector<int>> handles;  // rendered mug handles' pixels (dilated 2 px)
};

struct Method {
  std::string name;
  std::function<cv::Mat(const Input&)> run;  // the pixels it finds (CV_8U); timing covers the call
  std::vector<double> ms_synthetic, ms_real, recall_synthetic, recall_real;
};

cv::Mat blank(const Input& in) { return cv::Mat(in.grey.size(), CV_8U, cv::Scalar(0)); }

cv::Mat draw_lines(const Input& in, const std::vector<cv::Vec4f>& lines) {
  cv::Mat m = blank(in);
  for (const auto& l : lines) cv::line(m, cv::Point2f(l[0], l[1]), cv::Point2f(l[2], l[3]), 255, 1);
  return m;
}

cv::Mat segment_pixels(const Input& in, const std::vector<Segment>& s) {
  return bench::segment_mask(s, in.grey.rows, in.grey.cols);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  for (int i = 1; i < argc; ++i) quick |= std::strcmp(argv[i], "--quick") == 0;
  const int n_synthetic = quick ? 2 : 12, reps = quick ? 1 : 3;

  std::vector<Input> inputs;
  int handles_seen = 0, handles_with_arc = 0;
  // distinct scenes for the two depth models (the colour image does not depend on the model;
  // the lifting does)
  for (auto model : {synthetic::DepthModel::Kinect, synthetic::DepthModel::Stereo})
    for (int s = 0; s < n_synthetic; ++s) {
      synthetic::SceneOptions so;
      so.depth_model = model;
      so.handle_shapes = synthetic::HandleShapes::Varied;
      const std::uint64_t seed = 9300 + std::uint64_t(s) + (model == synthetic::DepthModel::Stereo ? 100 : 0);
      auto sf = synthetic::render(seed, so);
      Input in;
      in.name = std::string(model == synthetic::DepthModel::Stereo ? "stereo:" : "kinect:") + std::to_string(seed);
      in.synthetic = true;
      in.frame = sf.frame;
      in.outline = bench::outline_pixels(sf.truth.objects, sf.frame.color, [&](std::uint32_t l) {
        const auto* o = sf.truth.object(l);
        return o && o->model != "table" && o->model != "floor" && o->model != "wall";
      });
      for (const auto& o : sf.truth.objects_truth)
        if (const auto* h = o.part("handle"); h && o.model == "mug" && h->visible_pixels >= 150) {
          cv::Mat m(sf.frame.rows(), sf.frame.cols(), CV_8U, cv::Scalar(0));
          for (std::size_t i = 0; i < sf.truth.parts.pixels(); ++i)
            if (sf.truth.parts.data()[i] == h->label) m.data[i] = 255;
          cv::dilate(m, m, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
          std::vector<int> px;
          for (int i = 0; i < int(m.total()); ++i)
            if (m.data[i]) px.push_back(i);
          in.handles.push_back(std::move(px));
        }
      inputs.push_back(std::move(in));
    }
  const fs::path nv = fs::path(MEREO_REAL_DATA) / "nv-6dof-graspnet";
  if (fs::is_directory(nv)) {
    const io::Sequence seq = io::open({nv.string()});
    for (std::size_t i = 0; i < seq.size() && (!quick || i < 2); ++i) {
      Input in;
      in.frame = seq.load(i);
      in.name = "nv:" + in.frame.id;
      cv::Mat mask = cv::imread((nv / (in.frame.id + "-mask.png")).string(), cv::IMREAD_GRAYSCALE);
      if (mask.empty() || mask.cols != in.frame.cols()) continue;
      cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
      LabelImage labels(mask.rows, mask.cols, 0);
      for (int k = 0; k < int(mask.total()); ++k) labels.data()[k] = mask.data[k] ? 1 : 0;
      in.outline = bench::outline_pixels(labels, in.frame.color, [](std::uint32_t l) { return l == 1; });
      inputs.push_back(std::move(in));
    }
  } else {
    std::printf("real frames skipped: %s not found (it lies beside the repository, in ../shared)\n", nv.c_str());
  }
  for (auto& in : inputs) {
    const cv::Mat rgb(in.frame.rows(), in.frame.cols(), CV_8UC3, in.frame.color.data());
    cv::cvtColor(rgb, in.grey, cv::COLOR_RGB2GRAY);
    in.cloud = extension::back_project(in.frame);
  }

  std::vector<Method> methods;
  std::vector<Segment> last;  // mereo's segments of the frame just run, for the handle figure
  // mereo's lines and arcs with options `o` (keep: where the segments of the frame just run go)
  auto mereo_method = [](const char* name, const features::EdgePrimitiveOptions& o, std::vector<Segment>* keep) {
    return Method{name, [o, keep](const Input& in) {
                    auto s = features::fit_edge_primitives(signal::detect_edges(in.frame.color, o.edges), in.frame.color,
                                                           &in.cloud, o);
                    cv::Mat m = segment_pixels(in, s);
                    if (keep) *keep = std::move(s);
                    return m;
                  }};
  };
  features::EdgePrimitiveOptions fixed, ed_chains;
  fixed.edges.texture_factor = 0;  // the threshold not raised on texture
  ed_chains.edges.method = signal::EdgeMethod::EdgeDrawing;
  methods.push_back(mereo_method("mereo lines+arcs", {}, &last));
  methods.push_back(mereo_method("mereo, fixed threshold", fixed, nullptr));
  methods.push_back(mereo_method("mereo on Edge Drawing's chains", ed_chains, nullptr));
  methods.push_back({"OpenCV Canny 50/150", [](const Input& in) {
                       cv::Mat b, e;
                       cv::GaussianBlur(in.grey, b, cv::Size(), 1.0);
                       cv::Canny(b, e, 50, 150);
                       return e;
                     }});
  methods.push_back({"OpenCV FastLineDetector", [](const Input& in) {
                       static const auto fld = cv::ximgproc::createFastLineDetector();
                       std::vector<cv::Vec4f> lines;
                       fld->detect(in.grey, lines);
                       return draw_lines(in, lines);
                     }});
  methods.push_back({"OpenCV LSD", [](const Input& in) {
                       static const auto lsd = cv::createLineSegmentDetector();
                       std::vector<cv::Vec4f> lines;
                       lsd->detect(in.grey, lines);
                       return draw_lines(in, lines);
                     }});
  methods.push_back({"OpenCV EdgeDrawing lines+ellipses", [](const Input& in) {
                       auto ed = cv::ximgproc::createEdgeDrawing();
                       ed->detectEdges(in.grey);
                       std::vector<cv::Vec4f> lines;
                       std::vector<cv::Vec6d> ellipses;
                       ed->detectLines(lines);
                       ed->detectEllipses(ellipses);
                       cv::Mat m = draw_lines(in, lines);
                       for (const auto& e : ellipses) {  // (cx, cy, a, b, angle, 0)
                         const double a = e[2] + e[3], b = e[2] + e[4];  // ED writes circles as (cx, cy, r, 0, 0, 0)
                         cv::ellipse(m, cv::Point2d(e[0], e[1]), cv::Size2d(a, b), e[5], 0, 360, 255, 1);
                       }
                       return m;
                     }});

  for (int r = 0; r < reps; ++r)
    for (const auto& in : inputs)
      for (auto& m : methods) {
        const double t0 = now_ms();
        const cv::Mat hit = m.run(in);
        (in.synthetic ? m.ms_synthetic : m.ms_real).push_back(now_ms() - t0);
        if (r == 0) (in.synthetic ? m.recall_synthetic : m.recall_real).push_back(bench::outline_recall(in.outline, hit, 2));
        if (r == 0 && &m == &methods.front())
          for (const auto& h : in.handles) {  // an arc mostly on the handle
            std::vector<std::uint8_t> on(in.grey.total(), 0);
            for (int i : h) on[std::size_t(i)] = 1;
            bool found = false;
            for (const auto& x : last)
              if (x.is<shapes::Arc>()) {
                std::size_t n = 0;
                for (int i : x.pixels) n += on[std::size_t(i)];
                found |= 2 * n >= x.pixels.size();
              }
            ++handles_seen, handles_with_arc += found;
          }
      }

  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? NAN : s / double(v.size());
  };
  const std::size_t n_real = methods.front().recall_real.size();
  std::printf("%zu rendered frames (Kinect and stereo, varied handles), %zu real frames (nv-6dof-graspnet), %d repetitions\n",
              methods.front().recall_synthetic.size(), n_real, reps);
  std::printf("%-36s %16s %12s %16s %12s\n", "method", "rendered ms", "recall", "real ms", "recall");
  for (const auto& m : methods)
    std::printf("%-36s %16.2f %12.3f %16.2f %12.3f\n", m.name.c_str(), median(m.ms_synthetic), mean(m.recall_synthetic),
                median(m.ms_real), mean(m.recall_real));
  const Method& ed = methods.back();
  std::printf("mereo's time against Edge Drawing's own lines and ellipses: %.2fx rendered, %.2fx real\n",
              median(methods[0].ms_synthetic) / median(ed.ms_synthetic), median(methods[0].ms_real) / median(ed.ms_real));
  const double worst_ms = std::max(median(methods[0].ms_synthetic), n_real ? median(methods[0].ms_real) : 0.0);
  std::printf("the edge stage's target, at most 10 ms per VGA frame (median per set): %s (%.2f ms at worst)\n",
              worst_ms <= 10 ? "met" : "missed", worst_ms);
  std::printf("arcs on rendered mug handles showing >= 150 pixels: %d of %d\n", handles_with_arc, handles_seen);

  // Depth from a second camera registered to the colour camera before colour meets depth
  // (signal::register_depth, NYU's Kinect calibration) against OpenCV's rgbd::registerDepth, which
  // does the same (test_register: the same result), on every frame's depth.
  const DepthCamera nyu_depth{{582.62, 582.69, 313.04, 238.44}, [] {
                                Pose T = Pose::Identity();
                                T.translation() = Eigen::Vector3d(-0.025, 0.0003, -0.0007);
                                return T;
                              }()};
  const Intrinsics nyu_colour{518.86, 519.47, 325.58, 253.74};
  std::vector<double> ms_register, ms_opencv;
  for (int r = 0; r < reps; ++r)
    for (const auto& in : inputs) {
      const DepthImage& d = in.frame.depth;
      double t0 = now_ms();
      const DepthImage out = signal::register_depth(d, nyu_depth, nyu_colour, d.rows(), d.cols());
      ms_register.push_back(now_ms() - t0);
      cv::Mat z(d.rows(), d.cols(), CV_32F), reg;
      for (int i = 0; i < int(d.pixels()); ++i) z.at<float>(i) = std::isfinite(d.data()[i]) ? d.data()[i] : 0.f;
      const cv::Matx33d Kd(582.62, 0, 313.04, 0, 582.69, 238.44, 0, 0, 1), Kc(518.86, 0, 325.58, 0, 519.47, 253.74, 0, 0, 1);
      cv::Matx44d Rt = cv::Matx44d::eye();
      Rt(0, 3) = -0.025, Rt(1, 3) = 0.0003, Rt(2, 3) = -0.0007;
      t0 = now_ms();
      cv::rgbd::registerDepth(Kd, Kc, cv::noArray(), Rt, z, cv::Size(d.cols(), d.rows()), reg, false);
      ms_opencv.push_back(now_ms() - t0);
    }
  std::printf("depth registered to the colour camera: mereo %.2f ms, OpenCV's registerDepth %.2f ms (%.2fx), %zu runs\n",
              median(ms_register), median(ms_opencv), median(ms_register) / median(ms_opencv), ms_register.size());
  std::printf("{\"bench\":\"edges\",\"register_ms\":%s,\"register_opencv_ms\":%s",
              bench::json_number(median(ms_register), 2).c_str(), bench::json_number(median(ms_opencv), 2).c_str());
  for (const auto& m : methods)
    std::printf(",\"%s\":{\"ms\":%s,\"recall\":%s,\"ms_real\":%s,\"recall_real\":%s}", m.name.c_str(),
                bench::json_number(median(m.ms_synthetic), 2).c_str(), bench::json_number(mean(m.recall_synthetic)).c_str(),
                bench::json_number(median(m.ms_real), 2).c_str(), bench::json_number(mean(m.recall_real)).c_str());
  std::printf(",\"handle_arcs\":%d,\"handles\":%d,\"target_10ms_met\":%s}\n", handles_with_arc, handles_seen,
              worst_ms <= 10 ? "true" : "false");
  return 0;
}
