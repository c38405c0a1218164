// The judgement step and the JSON result of a frame (see interpret.hpp).
#include "mereo/matching/interpret.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

namespace mereo::matching {
namespace {

void segments_of(const Hypothesis& h, std::set<int>& out) {
  for (int s : h.assignment)
    if (s >= 0) out.insert(s);
  for (const auto& c : h.children) segments_of(c, out);
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string vec(const Eigen::Vector3d& v) { return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]"; }

}  // namespace

std::vector<RecognizedObject> interpret(const knowledge::KnowledgeBase& kb, const Lattice& lattice,
                                        const InterpretOptions& o) {
  const auto& H = lattice.hypotheses;
  std::map<std::string, knowledge::Concept> concepts;
  std::vector<std::set<int>> segs(H.size());
  for (std::size_t i = 0; i < H.size(); ++i) {
    segments_of(H[i], segs[i]);
    if (!concepts.count(H[i].concept_name))
      concepts.emplace(H[i].concept_name, knowledge::select(kb.resolve(H[i].concept_name)));
  }
  // Between hypotheses that explain as many segments equally well, the more specific concept
  // wins (a can over a jar for a 66 mm body): the data are likelier under the narrower ranges
  // (Occam's factor), measured as the sum of the log widths of the attribute ranges of the
  // parts present.
  std::vector<double> breadth(H.size(), 0.0);
  for (std::size_t i = 0; i < H.size(); ++i) {
    const auto& c = concepts.at(H[i].concept_name);
    for (const auto& a : c.attributes) {
      const int k = c.part_index(a.part);
      if (k < 0 || k >= int(H[i].assignment.size()) || H[i].assignment[k] < 0) continue;
      const double width = a.range.d - a.range.a;
      if (std::isfinite(width)) breadth[i] += std::log(std::max(1e-6, width));  // (one-sided ranges: no width)
    }
  }
  std::vector<int> order(H.size());
  for (std::size_t i = 0; i < H.size(); ++i) order[i] = int(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (segs[a].size() != segs[b].size()) return segs[a].size() > segs[b].size();
    if (std::abs(H[a].score - H[b].score) > 1e-9) return H[a].score > H[b].score;
    return breadth[a] < breadth[b] - 1e-9;
  });
  std::set<int> used;
  std::vector<int> accepted, listed;
  for (int i : order) {
    if (H[i].score < o.list_score) continue;
    bool free = true;
    for (int s : segs[i]) free = free && !used.count(s);
    if (free && H[i].score >= o.min_score && H[i].posterior >= o.min_posterior) {
      accepted.push_back(i);
      used.insert(segs[i].begin(), segs[i].end());
    } else {
      listed.push_back(i);
    }
  }
  std::stable_sort(accepted.begin(), accepted.end(), [&](int a, int b) { return H[a].score > H[b].score; });
  std::vector<RecognizedObject> out;
  for (int pass = 0; pass < 2; ++pass)
    for (int i : pass == 0 ? accepted : listed) {
      RecognizedObject r;
      r.id = int(out.size());
      r.model = H[i].concept_name;
      r.score = H[i].score;
      r.posterior = H[i].posterior;
      r.accepted = pass == 0;
      r.hypothesis = i;
      const auto& c = concepts.at(H[i].concept_name);
      for (std::size_t k = 0; k < c.parts.size() && k < H[i].assignment.size(); ++k)
        if (H[i].assignment[k] >= 0) r.parts.emplace_back(c.parts[k].role, H[i].assignment[k]);
      out.push_back(std::move(r));
    }
  for (auto& a : out)
    for (const auto& b : out) {
      if (a.id == b.id) continue;
      bool share = false;
      for (int s : segs[a.hypothesis]) share = share || segs[b.hypothesis].count(s);
      if (share) a.excludes.push_back(b.id);
    }
  return out;
}

std::string segment_json(const Segment& s) {
  std::ostringstream j;
  j << "{\"class\": " << quoted(to_string(s.cls));
  switch (s.cls) {
    case PrimitiveClass::Plane:
      j << ", \"normal\": " << vec(s.axis) << ", \"d\": " << num(s.d) << ", \"point\": " << vec(s.point);
      break;
    case PrimitiveClass::Cylinder:
      j << ", \"point\": " << vec(s.point) << ", \"axis\": " << vec(s.axis) << ", \"radius\": " << num(s.radius)
        << ", \"height\": " << num(s.height) << ", \"inward\": " << (s.inward ? "true" : "false");
      break;
    case PrimitiveClass::Torus:
      j << ", \"center\": " << vec(s.point) << ", \"normal\": " << vec(s.axis) << ", \"major_radius\": " << num(s.radius)
        << ", \"minor_radius\": " << num(s.minor_radius);
      break;
    case PrimitiveClass::Sphere:
      j << ", \"center\": " << vec(s.point) << ", \"radius\": " << num(s.radius)
        << ", \"inward\": " << (s.inward ? "true" : "false");
      break;
    default:
      j << ", \"point\": " << vec(s.point) << ", \"axis\": " << vec(s.axis);
  }
  j << ", \"inliers\": " << s.inliers << ", \"residual\": " << num(s.residual) << ", \"hue\": " << num(s.hue) << "}";
  return j.str();
}

std::string result_json(const Frame& frame, const std::vector<Segment>& segments,
                        const std::vector<RecognizedObject>& objects, const extension::SupportPlane* plane,
                        const std::vector<std::pair<std::string, double>>& timing_ms,
                        const std::string& objects_array) {
  std::ostringstream j;
  j << "{\"frame\": " << quoted(frame.id) << ", \"source\": " << quoted(frame.source) << ", \"objects\": ";
  if (!objects_array.empty()) j << objects_array.substr(0, objects_array.size() - 1);  // (its "]" follows)
  else j << "[";
  for (std::size_t k = 0; k < objects.size() && objects_array.empty(); ++k) {
    const auto& o = objects[k];
    j << (k ? ", " : "") << "{\"id\": " << o.id << ", \"model\": " << quoted(o.model) << ", \"score\": " << num(o.score)
      << ", \"posterior\": " << num(o.posterior) << ", \"accepted\": " << (o.accepted ? "true" : "false")
      << ", \"parts\": {";
    for (std::size_t p = 0; p < o.parts.size(); ++p) {
      const Segment& s = segments.at(std::size_t(o.parts[p].second));
      std::string sj = segment_json(s);
      sj.insert(1, "\"segment\": " + std::to_string(o.parts[p].second) + ", ");
      j << (p ? ", " : "") << quoted(o.parts[p].first) << ": " << sj;
    }
    j << "}, \"excludes\": [";
    for (std::size_t e = 0; e < o.excludes.size(); ++e) j << (e ? ", " : "") << o.excludes[e];
    j << "]}";
  }
  j << "], \"primitives\": [";
  for (std::size_t k = 0; k < segments.size(); ++k) {
    std::string sj = segment_json(segments[k]);
    sj.insert(1, "\"id\": " + std::to_string(k) + ", ");
    j << (k ? ", " : "") << sj;
  }
  j << "]";
  if (plane && plane->inlier_count > 0)
    j << ", \"support_plane\": {\"normal\": " << vec(plane->normal) << ", \"d\": " << num(plane->d)
      << ", \"inliers\": " << plane->inlier_count << ", \"rms\": " << num(plane->rms) << "}";
  if (!timing_ms.empty()) {
    j << ", \"timing_ms\": {";
    for (std::size_t k = 0; k < timing_ms.size(); ++k)
      j << (k ? ", " : "") << quoted(timing_ms[k].first) << ": " << num(timing_ms[k].second);
    j << "}";
  }
  j << "}";
  return j.str();
}

}  // namespace mereo::matching
