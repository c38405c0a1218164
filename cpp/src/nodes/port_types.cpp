// The library's port types: each C++ type that crosses a graph edge, with its name and a
// one-line summary (what mereo-run prints for an output).
#include <cmath>
#include <sstream>
#include <type_traits>

#include "mereo/cognitive/tracking.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "mereo/matching/interpret.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

namespace {

template <typename T, int C>
std::string image_text(const Image<T, C>& im, const char* what) {
  std::ostringstream s;
  s << im.cols() << "x" << im.rows() << " " << what;
  if (C == 3 && std::is_floating_point<T>::value) {
    std::size_t valid = 0;
    for (std::size_t i = 0; i < im.pixels(); ++i) valid += std::isfinite(float(im.data()[C * i + C - 1]));
    s << ", " << (im.pixels() ? 100.0 * valid / im.pixels() : 0.0) << "% valid";
  }
  return s.str();
}

}  // namespace

void register_port_types() {
  using graph::register_type;
  register_type<Frame>("Frame", [](const Frame& f) {
    return "frame " + f.id + " " + std::to_string(f.cols()) + "x" + std::to_string(f.rows());
  });
  register_type<Cloud>("Cloud", [](const Cloud& c) { return image_text(c, "cloud"); });
  register_type<NormalMap>("NormalMap", [](const NormalMap& c) { return image_text(c, "normal map"); });
  register_type<DepthImage>("Depth", [](const DepthImage& c) { return image_text(c, "depth image"); });
  register_type<ColorImage>("Color", [](const ColorImage& c) { return image_text(c, "colour image"); });
  register_type<LabelImage>("Labels", [](const LabelImage& c) { return image_text(c, "label image"); });
  register_type<extension::Mask>("Mask", [](const extension::Mask& c) { return image_text(c, "mask"); });
  register_type<extension::SupportPlane>("SupportPlane", [](const extension::SupportPlane& p) {
    std::ostringstream s;
    s.precision(4);
    s << "plane n=(" << p.normal.x() << ", " << p.normal.y() << ", " << p.normal.z() << ") d=" << p.d
      << ", " << p.inlier_count << " inliers, " << p.polygon.size() << "-gon";
    return s.str();
  });
  register_type<matching::Lattice>("Lattice", [](const matching::Lattice& l) {
    std::ostringstream s;
    s << l.hypotheses.size() << " hypotheses, " << l.excludes.size() << " exclusions";
    if (!l.hypotheses.empty()) s << ", best " << l.hypotheses.front().concept_name << " " << l.hypotheses.front().score;
    return s.str();
  });
  register_type<knowledge::ModelSet>("ModelSet", [](const knowledge::ModelSet& m) {
    std::string names;
    for (const auto& c : m.concepts) names += (names.empty() ? "" : ", ") + c;
    return std::to_string(m.kb.names().size()) + " concepts, looking for " + (names.empty() ? "none" : names);
  });
  register_type<std::vector<matching::RecognizedObject>>("Interpretation", [](const std::vector<matching::RecognizedObject>& v) {
    std::size_t accepted = 0;
    for (const auto& o : v) accepted += o.accepted;
    return std::to_string(accepted) + " accepted objects, " + std::to_string(v.size() - accepted) + " alternatives";
  });
  register_type<std::vector<cognitive::Track>>("Tracks", [](const std::vector<cognitive::Track>& t) {
    std::size_t reported = 0;
    for (const auto& x : t) reported += x.probability() >= 0.5;
    return std::to_string(t.size()) + " tracks, " + std::to_string(reported) + " reported";
  });
  register_type<std::vector<Segment>>("Segments", [](const std::vector<Segment>& s) {
    return std::to_string(s.size()) + " segments";
  });
}

}  // namespace mereo::nodes
