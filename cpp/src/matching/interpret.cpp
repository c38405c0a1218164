// The judgement step and the JSON result of a frame (see interpret.hpp).
#include "mereo/matching/interpret.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <Eigen/Geometry>

#include "matching/json.hpp"
#include "mereo/knowledge/predicates.hpp"
#include "shapes/json.hpp"

namespace mereo::matching {
namespace {

void segments_of(const Hypothesis& h, std::set<int>& out) {
  for (int s : h.assignment)
    if (s >= 0) out.insert(s);
  for (const auto& c : h.children) segments_of(c, out);
}

}  // namespace

std::vector<RecognizedObject> interpret(const knowledge::KnowledgeBase& kb, const Lattice& lattice,
                                        const InterpretOptions& o) {
  const auto& H = lattice.hypotheses;
  // the part set of each hypothesis: its concept's modality
  std::map<std::pair<std::string, std::string>, knowledge::Concept> concepts;
  const auto concept_of = [&](const Hypothesis& h) -> const knowledge::Concept& {
    return concepts.at({h.concept_name, h.modality});
  };
  std::vector<std::set<int>> segs(H.size());
  for (std::size_t i = 0; i < H.size(); ++i) {
    segments_of(H[i], segs[i]);
    const std::pair<std::string, std::string> key{H[i].concept_name, H[i].modality};
    if (!concepts.count(key)) concepts.emplace(key, knowledge::select(kb.resolve(H[i].concept_name), H[i].modality));
  }
  // Between hypotheses that explain as many segments equally well, the more specific concept
  // wins (a can over a jar for a 66 mm body): the data are likelier under the narrower ranges
  // (Occam's factor), measured as the sum of the log widths of the attribute ranges of the
  // parts present. Where those are as wide, the more general concept wins: nothing seen tells
  // the specialization (a chair seen from behind, whose legs a dining chair would show).
  std::vector<double> breadth(H.size(), 0.0);
  std::vector<std::size_t> depth(H.size(), 0);
  for (std::size_t i = 0; i < H.size(); ++i) {
    const auto& c = concept_of(H[i]);
    depth[i] = kb.ancestors(H[i].concept_name).size();
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
    if (std::abs(breadth[a] - breadth[b]) > 1e-9) return breadth[a] < breadth[b];
    return depth[a] < depth[b];
  });
  std::set<int> used;
  std::vector<int> accepted, listed;
  std::set<std::pair<int, int>> same_place;
  if (o.one_per_place) same_place.insert(lattice.same_place.begin(), lattice.same_place.end());
  for (int i : order) {
    if (H[i].score < o.list_score) continue;
    bool free = true;
    for (int s : segs[i]) free = free && !used.count(s);
    for (int j : accepted) free = free && !same_place.count({std::min(i, j), std::max(i, j)});
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
      r.is_a = kb.ancestors(r.model);
      r.score = H[i].score;
      r.posterior = H[i].posterior;
      r.accepted = pass == 0;
      r.hypothesis = i;
      r.modality = H[i].modality;
      const auto& c = concept_of(H[i]);
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

namespace detail {

Json segment_to_json(const Segment& s) {
  Json j;
  j["class"] = s.class_name();
  shapes::fields_to_json(s.fields(), j);  // the class's own, mereo/shapes/*.cpp
  j["inliers"] = s.inliers, j["residual"] = s.residual, j["hue"] = s.hue;
  return j;
}

Json result_to_json(const Frame& frame, const std::vector<Segment>& segments,
                    const std::vector<RecognizedObject>& objects, const extension::SupportPlane* plane,
                    const std::vector<std::pair<std::string, double>>& timing_ms) {
  Json j;
  j["frame"] = frame.id, j["source"] = frame.source;
  j["objects"] = Json::array();
  for (const auto& o : objects) {
    Json obj;
    obj["id"] = o.id, obj["model"] = o.model, obj["is_a"] = o.is_a, obj["score"] = o.score, obj["posterior"] = o.posterior;
    if (!o.modality.empty()) obj["modality"] = o.modality;
    obj["accepted"] = o.accepted;
    obj["parts"] = Json::object();
    for (const auto& [role, k] : o.parts) {
      Json part;
      part["segment"] = k;
      part.update(segment_to_json(segments.at(std::size_t(k))));
      obj["parts"][role] = std::move(part);
    }
    obj["excludes"] = o.excludes;
    for (const auto& [role, k] : o.parts)  // upright or lying: the body's tilt from the table's normal
      if (role == "body" && plane) {
        const double tilt = knowledge::attribute_value(segments.at(std::size_t(k)), "tilt_deg", {plane->normal});
        if (std::isfinite(tilt)) obj["pose"] = tilt < 45 ? "upright" : "lying";
      }
    if (o.coverage >= 0) obj["coverage"] = o.coverage;
    if (!o.rejected.empty()) obj["rejected"] = o.rejected;
    if (o.region) {
      const auto& r = *o.region;
      obj["region"] = {{"pixels", r.indices.size()},
                       {"box", Json::array({r.box[0], r.box[1], r.box[2], r.box[3]})},
                       {"centroid", Json::array({r.centroid.x(), r.centroid.y(), r.centroid.z()})},
                       {"size", Json::array({r.size.x(), r.size.y(), r.size.z()})}};
    }
    j["objects"].push_back(std::move(obj));
  }
  j["primitives"] = Json::array();
  for (std::size_t k = 0; k < segments.size(); ++k) {
    Json p;
    p["id"] = k;
    p.update(segment_to_json(segments[k]));
    j["primitives"].push_back(std::move(p));
  }
  if (plane && plane->inlier_count > 0)
    j["support_plane"] = {{"normal", Json::array({plane->normal.x(), plane->normal.y(), plane->normal.z()})},
                          {"d", plane->d}, {"inliers", plane->inlier_count}, {"rms", plane->rms},
                          {"noise", plane->noise}};
  if (frame.pose) {  // camera to world, as TUM's groundtruth.txt writes it
    const Eigen::Quaterniond q(frame.pose->linear());
    const Eigen::Vector3d t = frame.pose->translation();
    j["camera_pose"] = {{"translation", Json::array({t.x(), t.y(), t.z()})},
                        {"quaternion", Json::array({q.x(), q.y(), q.z(), q.w()})}};
  }
  for (const auto& [node, ms] : timing_ms) j["timing_ms"][node] = ms;
  return j;
}

}  // namespace detail

std::string segment_json(const Segment& s) { return detail::segment_to_json(s).dump(); }

std::string result_json(const Frame& frame, const std::vector<Segment>& segments,
                        const std::vector<RecognizedObject>& objects, const extension::SupportPlane* plane,
                        const std::vector<std::pair<std::string, double>>& timing_ms) {
  return detail::result_to_json(frame, segments, objects, plane, timing_ms).dump();
}

}  // namespace mereo::matching
