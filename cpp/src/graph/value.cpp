#include "mereo/graph/value.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <mutex>
#include <sstream>

#include "mereo/cognitive/tracking.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/matching/match.hpp"

namespace mereo::graph {

namespace {

struct Registry {
  std::mutex mutex;
  std::deque<TypeInfo> types;  // deque: stable addresses
};

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

void register_builtin(Registry& r);

Registry& registry() {
  static Registry* r = [] {
    auto* reg = new Registry;
    register_builtin(*reg);
    return reg;
  }();
  return *r;
}

void add(Registry& r, const std::string& name, std::type_index t, std::function<std::string(const void*)> d) {
  for (auto& e : r.types)
    if (e.name == name) {
      if (e.type != t) throw std::logic_error("port type '" + name + "' registered for two C++ types");
      return;
    }
  r.types.push_back({name, t, std::move(d)});
}

template <typename T>
void add(Registry& r, const std::string& name, std::function<std::string(const T&)> d) {
  add(r, name, std::type_index(typeid(T)), [d](const void* p) { return d(*static_cast<const T*>(p)); });
}

// The built-in port types. A module that adds a type registers it here too, so that the
// list of types is in one place.
void register_builtin(Registry& r) {
  add<Frame>(r, "Frame", [](const Frame& f) {
    return "frame " + f.id + " " + std::to_string(f.cols()) + "x" + std::to_string(f.rows());
  });
  add<Cloud>(r, "Cloud", [](const Cloud& c) { return image_text(c, "cloud"); });
  add<NormalMap>(r, "NormalMap", [](const NormalMap& c) { return image_text(c, "normal map"); });
  add<DepthImage>(r, "Depth", [](const DepthImage& c) { return image_text(c, "depth image"); });
  add<ColorImage>(r, "Color", [](const ColorImage& c) { return image_text(c, "colour image"); });
  add<LabelImage>(r, "Labels", [](const LabelImage& c) { return image_text(c, "label image"); });
  add<extension::Mask>(r, "Mask", [](const extension::Mask& c) { return image_text(c, "mask"); });
  add<extension::SupportPlane>(r, "SupportPlane", [](const extension::SupportPlane& p) {
    std::ostringstream s;
    s.precision(4);
    s << "plane n=(" << p.normal.x() << ", " << p.normal.y() << ", " << p.normal.z() << ") d=" << p.d
      << ", " << p.inlier_count << " inliers, " << p.polygon.size() << "-gon";
    return s.str();
  });
  add<matching::Lattice>(r, "Lattice", [](const matching::Lattice& l) {
    std::ostringstream s;
    s << l.hypotheses.size() << " hypotheses, " << l.excludes.size() << " exclusions";
    if (!l.hypotheses.empty()) s << ", best " << l.hypotheses.front().concept_name << " " << l.hypotheses.front().score;
    return s.str();
  });
  add<std::vector<cognitive::Track>>(r, "Tracks", [](const std::vector<cognitive::Track>& t) {
    std::size_t reported = 0;
    for (const auto& x : t) reported += x.probability() >= 0.5;
    return std::to_string(t.size()) + " tracks, " + std::to_string(reported) + " reported";
  });
  add<std::vector<Segment>>(r, "Segments", [](const std::vector<Segment>& s) {
    return std::to_string(s.size()) + " segments";
  });
  add<double>(r, "Number", [](const double& x) {
    std::ostringstream s;
    s.precision(17);
    s << x;
    return s.str();
  });
  add<std::string>(r, "Text", [](const std::string& x) { return x; });
}

}  // namespace

const TypeInfo& type_of(std::type_index t) {
  auto& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& e : r.types)
    if (e.type == t) return e;
  throw std::logic_error(std::string("C++ type ") + t.name() + " is not a registered port type");
}

const TypeInfo* find_type(const std::string& name) {
  auto& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& e : r.types)
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> type_names() {
  auto& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& e : r.types) names.push_back(e.name);
  std::sort(names.begin(), names.end());
  return names;
}

void register_type(const std::string& name, std::type_index t, std::function<std::string(const void*)> d) {
  auto& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  add(r, name, t, std::move(d));
}

Value Value::as(const TypeInfo& type) const {
  if (!type_ || type.type != type_->type)
    throw std::logic_error("a value of type " + (type_ ? type_->name : std::string("(empty)")) +
                           " cannot pass as " + type.name);
  Value v = *this;
  v.type_ = &type;
  return v;
}

std::string Value::describe() const {
  if (!ptr_) return "(empty)";
  return type_->describe ? type_->describe(ptr_.get()) : type_->name;
}

}  // namespace mereo::graph
