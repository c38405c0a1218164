// Exhaustive and branch-and-bound matching of concepts to segments (see match.hpp).
#include "mereo/matching/match.hpp"

#include <algorithm>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <numeric>

#include <tbb/parallel_for.h>

#include "mereo/knowledge/bayes.hpp"

namespace mereo::matching {
namespace {

using knowledge::Concept;
using knowledge::Context;

/// The N best, kept sorted: score descending, then assignment ascending (lexicographic).
class Best {
 public:
  Best(std::size_t n, double min_score) : n_(n), min_(min_score) {}
  static bool better(const Hypothesis& a, const Hypothesis& b) {
    if (a.score != b.score) return a.score > b.score;
    return a.assignment < b.assignment;
  }
  void offer(Hypothesis h) {
    if (!(h.score >= min_) || !(h.score > 0)) return;
    if (items_.size() == n_ && !better(h, items_.back())) return;
    items_.insert(std::upper_bound(items_.begin(), items_.end(), h, better), std::move(h));
    if (items_.size() > n_) items_.pop_back();
  }
  bool full() const { return items_.size() == n_; }
  /// The score a branch must reach to matter (the worst kept, or the threshold).
  double floor() const { return full() ? std::max(min_, items_.back().score) : min_; }
  std::vector<Hypothesis> take() { return std::move(items_); }

 private:
  std::size_t n_;
  double min_;
  std::vector<Hypothesis> items_;
};

/// Constraint values of the constraints whose parts are all assigned (none missing), in index
/// order, for a complete or partial assignment (-1 missing, -2 undecided).
double constraint_product(const Concept& c, const std::vector<int>& a, const std::vector<Segment>& segs,
                          const Context& ctx, std::vector<double>* values = nullptr,
                          const std::vector<knowledge::CompiledConstraint>* compiled = nullptr) {
  double s = 1.0;
  std::vector<const Segment*> parts;
  for (std::size_t k = 0; k < c.constraints.size(); ++k) {
    const auto& con = c.constraints[k];
    parts.clear();
    bool all = true;
    for (const auto& role : con.parts) {
      const int i = c.part_index(role);
      if (a[i] < 0) {
        all = false;
        break;
      }
      parts.push_back(&segs[a[i]]);
    }
    const double v = !all ? -1.0 : compiled ? (*compiled)[k](parts, ctx) : knowledge::evaluate(con, parts, ctx);
    if (values) values->push_back(v);
    if (all) s *= v;
  }
  return s;
}

/// Symmetry breaking for interchangeable parts (Part::group): within a group, assigned segments
/// increase with the part index and missing parts come last. True if part i may take s (>= 0,
/// or -1 = missing) given the parts of its group assigned so far (-2 = undecided).
bool group_ok(const Concept& c, const std::vector<int>& a, int i, int s) {
  const std::string& g = c.parts[i].group;
  if (g.empty()) return true;
  for (int j = 0; j < int(c.parts.size()); ++j) {
    if (j == i || c.parts[j].group != g || a[j] == -2) continue;
    const int lo = j < i ? a[j] : s, hi = j < i ? s : a[j];  // the earlier part's and the later's
    if (lo == -1 && hi != -1) return false;                   // missing ones last
    if (lo >= 0 && hi >= 0 && lo >= hi) return false;         // increasing segments
  }
  return true;
}

struct Prepared {
  const Concept& c;
  const std::vector<Segment>& segs;
  const MatchOptions& o;
  /// The segments, then one stand-in per hypothesis of a sub-concept (a part whose class is a
  /// concept): a copy of the sub-hypothesis's first segment, its anchor for constraints.
  std::vector<Segment> ext;
  std::vector<Hypothesis> subs;              // [ext index - segs.size()]
  std::vector<std::vector<int>> uses;        // the real segments each sub-hypothesis takes
  std::vector<std::vector<double>> unary;  // [part][ext index]
  std::vector<std::vector<int>> domain;    // [part]: ext indices of the part's class
  /// constraints touching each part, and each constraint's part indices
  std::vector<std::vector<int>> touching;
  std::vector<std::vector<int>> members;
  std::vector<knowledge::CompiledConstraint> compiled;

  Prepared(const Concept& c_, const std::vector<Segment>& s_, const MatchOptions& o_) : c(c_), segs(s_), o(o_) {
    const std::size_t P = c.parts.size();
    ext = segs;
    std::vector<std::pair<std::size_t, std::size_t>> sub_range(P, {0, 0});  // ext indices per part
    for (std::size_t i = 0; i < P; ++i) {
      if (knowledge::is_primitive(c.parts[i].cls)) continue;
      // parts of the same concept class share one set of candidates (and so one order, which
      // the symmetry breaking of groups relies on)
      bool shared = false;
      for (std::size_t j = 0; j < i && !shared; ++j)
        if (c.parts[j].cls == c.parts[i].cls) sub_range[i] = sub_range[j], shared = true;
      if (shared) continue;
      if (!o.kb) throw std::invalid_argument("part '" + c.parts[i].role + "' of '" + c.name + "' is a " +
                                             c.parts[i].cls + ": matching it needs MatchOptions::kb");
      if (o.depth >= 8) throw std::invalid_argument("concepts nested deeper than 8 parts (a cycle?) at '" + c.name + "'");
      MatchOptions sub = o;
      sub.best = o.sub_best;
      sub.depth = o.depth + 1;
      const auto hyps = match(knowledge::select(o.kb->resolve(c.parts[i].cls)), segs, sub);
      sub_range[i] = {ext.size(), ext.size() + hyps.size()};
      for (const auto& h : hyps) {
        std::vector<int> taken;
        collect(h, taken);
        if (taken.empty()) continue;
        ext.push_back(segs[taken.front()]);
        subs.push_back(h);
        uses.push_back(taken);
      }
      sub_range[i].second = ext.size();
    }
    unary.assign(P, std::vector<double>(ext.size(), 0.0));
    domain.resize(P);
    touching.resize(P);
    for (std::size_t i = 0; i < P; ++i) {
      if (knowledge::is_primitive(c.parts[i].cls)) {
        for (std::size_t j = 0; j < segs.size(); ++j)
          if (segs[j].class_name() == c.parts[i].cls) {
            domain[i].push_back(int(j));
            unary[i][j] = part_score(c, int(i), segs[j], o.context);
          }
        continue;
      }
      for (std::size_t j = sub_range[i].first; j < sub_range[i].second; ++j) {
        double m = subs[j - segs.size()].score;  // the sub-hypothesis's score, times this part's ranges
        for (const auto& a : c.attributes)
          if (a.part == c.parts[i].role) m *= knowledge::attribute_membership(ext[j], a, o.context);
        domain[i].push_back(int(j));
        unary[i][j] = m;
      }
    }
    members.resize(c.constraints.size());
    for (const auto& con : c.constraints) compiled.push_back(knowledge::compile(con));
    for (std::size_t k = 0; k < c.constraints.size(); ++k)
      for (const auto& role : c.constraints[k].parts) {
        const int i = c.part_index(role);
        members[k].push_back(i);
        if (std::find(touching[i].begin(), touching[i].end(), int(k)) == touching[i].end())
          touching[i].push_back(int(k));
      }
  }

  /// The real segments of a hypothesis (its own and its sub-hypotheses').
  static void collect(const Hypothesis& h, std::vector<int>& out) {
    for (std::size_t i = 0; i < h.assignment.size(); ++i) {
      if (i < h.children.size() && !h.children[i].assignment.empty())
        collect(h.children[i], out);
      else if (h.assignment[i] >= 0)
        out.push_back(h.assignment[i]);
    }
  }
  /// Whether ext value v can be assigned (its segments are free), and taking / releasing it.
  bool available(const std::vector<char>& used, int v) const {
    if (v < int(segs.size())) return !used[v];
    for (int s : uses[v - segs.size()])
      if (used[s]) return false;
    return true;
  }
  void take(std::vector<char>& used, int v, char on) const {
    if (v < int(segs.size()))
      used[v] = on;
    else
      for (int s : uses[v - segs.size()]) used[s] = on;
  }
  /// Search results in the caller's terms: a sub-concept's part gets the sub-hypothesis's first
  /// segment in `assignment` and the sub-hypothesis in `children`.
  std::vector<Hypothesis> finish(std::vector<Hypothesis> hyps) const {
    if (subs.empty()) return hyps;
    for (auto& h : hyps) {
      h.children.assign(h.assignment.size(), Hypothesis{});
      for (std::size_t i = 0; i < h.assignment.size(); ++i)
        if (h.assignment[i] >= int(segs.size())) {
          h.children[i] = subs[h.assignment[i] - segs.size()];
          h.assignment[i] = uses[h.assignment[i] - segs.size()].front();
        }
    }
    return hyps;
  }

  /// The hypothesis of a complete assignment: hypothesis_score() and judge(), computed with the
  /// cached memberships and compiled constraints (the same numbers, in the same order).
  Hypothesis make(const std::vector<int>& a) const {
    Hypothesis h;
    h.concept_name = c.name;
    h.assignment = a;
    knowledge::Evidence e;
    double s = 1.0;
    for (std::size_t i = 0; i < c.parts.size(); ++i) {
      const double q = a[i] >= 0 ? unary[i][a[i]] : 0.0;
      s *= a[i] >= 0 ? q : c.parts[i].missing_score;
      e.state.push_back(a[i] >= 0 ? knowledge::PartState::Present
                                  : a[i] == -1 ? knowledge::PartState::Missing : knowledge::PartState::Undecided);
      e.quality.push_back(q);
    }
    h.score = s * constraint_product(c, a, ext, o.context, &e.satisfied, &compiled);
    h.posterior = knowledge::posterior(c, e);
    return h;
  }
};

}  // namespace

double part_score(const Concept& c, int part, const Segment& s, const Context& ctx) {
  if (s.class_name() != c.parts.at(part).cls) return 0.0;
  double m = 1.0;
  for (const auto& a : c.attributes)
    if (a.part == c.parts[part].role) m *= knowledge::attribute_membership(s, a, ctx);
  return m;
}

double hypothesis_score(const Concept& c, const std::vector<int>& a, const std::vector<Segment>& segs,
                        const Context& ctx) {
  double s = 1.0;
  for (std::size_t i = 0; i < c.parts.size(); ++i)
    s *= a[i] >= 0 ? part_score(c, int(i), segs[a[i]], ctx) : c.parts[i].missing_score;
  return s * constraint_product(c, a, segs, ctx);
}

double judge(const Concept& c, const std::vector<int>& a, const std::vector<Segment>& segs, const Context& ctx) {
  knowledge::Evidence e;
  for (std::size_t i = 0; i < c.parts.size(); ++i) {
    e.state.push_back(a[i] >= 0 ? knowledge::PartState::Present
                                : a[i] == -1 ? knowledge::PartState::Missing : knowledge::PartState::Undecided);
    e.quality.push_back(a[i] >= 0 ? part_score(c, int(i), segs[a[i]], ctx) : 0.0);
  }
  constraint_product(c, a, segs, ctx, &e.satisfied);
  return knowledge::posterior(c, e);
}

std::vector<Hypothesis> match_exhaustive(const Concept& c, const std::vector<Segment>& segs, const MatchOptions& o,
                                         MatchStats* stats) {
  const Prepared pr(c, segs, o);
  Best best(std::size_t(std::max(1, o.best)), o.min_score);
  MatchStats st;
  const std::size_t P = c.parts.size();
  std::vector<int> a(P, -2);
  std::vector<char> used(segs.size(), 0);
  std::function<void(std::size_t)> rec = [&](std::size_t i) {
    ++st.expanded;
    if (i == P) {
      ++st.complete;
      best.offer(pr.make(a));
      return;
    }
    for (int s : pr.domain[i]) {
      if (!pr.available(used, s) || !group_ok(c, a, int(i), s)) continue;
      pr.take(used, s, 1), a[i] = s;
      rec(i + 1);
      pr.take(used, s, 0);
    }
    if (c.parts[i].optional && group_ok(c, a, int(i), -1)) {
      a[i] = -1;
      rec(i + 1);
    }
    a[i] = -2;
  };
  rec(0);
  if (stats) *stats = st;
  return pr.finish(best.take());
}

std::vector<Hypothesis> match(const Concept& c, const std::vector<Segment>& segs, const MatchOptions& o,
                              MatchStats* stats) {
  const Prepared pr(c, segs, o);
  Best best(std::size_t(std::max(1, o.best)), o.min_score);
  MatchStats st;
  const std::size_t P = c.parts.size();
  const Context& ctx = o.context;

  // values of each part, best-scoring first: (segment, unary); -1 = missing
  std::vector<std::vector<std::pair<int, double>>> values(P);
  for (std::size_t i = 0; i < P; ++i) {
    for (int s : pr.domain[i])
      if (pr.unary[i][s] > 0) values[i].push_back({s, pr.unary[i][s]});
    if (c.parts[i].optional) values[i].push_back({-1, c.parts[i].missing_score});
    std::stable_sort(values[i].begin(), values[i].end(),
                     [](const auto& x, const auto& y) { return x.second > y.second; });
  }
  // most-constrained part first: fewest values, then most constraints, then model order
  std::vector<int> order(P);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) {
    if (values[x].size() != values[y].size()) return values[x].size() < values[y].size();
    return pr.touching[x].size() > pr.touching[y].size();
  });

  std::vector<int> a(P, -2);
  std::vector<char> used(segs.size(), 0);
  std::vector<const Segment*> args;
  // value of constraint k if all its parts are assigned (none missing) with part `i` set to `s`
  auto constraint_with = [&](int k, int i, int s, bool& complete) {
    args.clear();
    complete = true;
    for (const int j : pr.members[k]) {
      const int v = j == i ? s : a[j];
      if (v < 0) {
        complete = false;
        return 1.0;
      }
      args.push_back(&pr.ext[v]);
    }
    return pr.compiled[k](args, ctx);
  };
  // forward checking: the best factor part i can still bring, given the assigned parts
  auto best_value = [&](int i) {
    double m = 0.0;
    for (const auto& [s, u] : values[i]) {
      if (u <= m) break;  // sorted: no later value can beat m
      if ((s >= 0 && !pr.available(used, s)) || !group_ok(c, a, i, s)) continue;
      double v = u;
      if (s >= 0)
        for (int k : pr.touching[i]) {
          bool complete;
          const double f = constraint_with(k, i, s, complete);
          if (complete) v *= f;
          if (v <= m) break;
        }
      m = std::max(m, v);
    }
    return m;
  };
  const double slack = 1 + 1e-9;  // bounds are products in another order than the final score

  std::function<void(std::size_t, double)> rec = [&](std::size_t depth, double partial) {
    ++st.expanded;
    if (depth == P) {
      ++st.complete;
      best.offer(pr.make(a));
      return;
    }
    const int i = order[depth];
    for (const auto& [s, u] : values[i]) {
      if ((s >= 0 && !pr.available(used, s)) || !group_ok(c, a, i, s)) continue;
      // the factor of this value: its unary score and the constraints it completes
      double f = u;
      if (s >= 0)
        for (int k : pr.touching[i]) {
          bool complete;
          const double v = constraint_with(k, i, s, complete);
          if (complete) f *= v;
        }
      const double next = partial * f;
      if (next * slack < best.floor()) {
        ++st.pruned;
        continue;
      }
      a[i] = s;
      if (s >= 0) pr.take(used, s, 1);
      // upper bound: every unassigned part at its best given what is assigned now
      double bound = next;
      for (std::size_t d = depth + 1; d < P && bound * slack >= best.floor(); ++d) bound *= best_value(order[d]);
      if (bound * slack < best.floor())
        ++st.pruned;
      else
        rec(depth + 1, next);
      if (s >= 0) pr.take(used, s, 0);
      a[i] = -2;
    }
  };
  rec(0, 1.0);
  if (stats) *stats = st;
  return pr.finish(best.take());
}

Lattice recognize(const knowledge::KnowledgeBase& kb, const std::vector<std::string>& concepts,
                  const std::vector<Segment>& segments, const MatchOptions& options) {
  // every modality of a concept is matched as a concept of its own (the method's OR links)
  std::vector<Concept> resolved;
  std::vector<std::string> modality;
  for (const auto& name : concepts) {
    const Concept full = kb.resolve(name);
    if (full.modalities.empty()) resolved.push_back(knowledge::select(full)), modality.emplace_back();
    for (const auto& m : full.modalities) resolved.push_back(knowledge::select(full, m.name)), modality.push_back(m.name);
  }
  std::vector<std::vector<Hypothesis>> found(resolved.size());
  std::vector<MatchStats> stats(resolved.size());
  MatchOptions o = options;
  o.kb = &kb;
  tbb::parallel_for(std::size_t(0), resolved.size(),
                    [&](std::size_t i) { found[i] = match(resolved[i], segments, o, &stats[i]); });
  Lattice out;
  for (std::size_t i = 0; i < found.size(); ++i) {
    for (auto& h : found[i]) {
      h.modality = modality[i];
      out.hypotheses.push_back(std::move(h));
    }
    out.stats.expanded += stats[i].expanded;
    out.stats.pruned += stats[i].pruned;
    out.stats.complete += stats[i].complete;
  }
  std::vector<std::vector<int>> taken(out.hypotheses.size());
  for (std::size_t i = 0; i < out.hypotheses.size(); ++i) {
    Prepared::collect(out.hypotheses[i], taken[i]);
    std::sort(taken[i].begin(), taken[i].end());
  }
  for (std::size_t i = 0; i < out.hypotheses.size(); ++i)
    for (std::size_t j = i + 1; j < out.hypotheses.size(); ++j) {
      std::vector<int> common;
      std::set_intersection(taken[i].begin(), taken[i].end(), taken[j].begin(), taken[j].end(),
                            std::back_inserter(common));
      if (!common.empty()) out.excludes.push_back({int(i), int(j)});
    }
  for (std::size_t i = 0; i < out.hypotheses.size(); ++i)
    for (std::size_t j = i + 1; j < out.hypotheses.size(); ++j) {
      const Hypothesis &a = out.hypotheses[i], &b = out.hypotheses[j];
      if (a.concept_name != b.concept_name || a.modality != b.modality || !a.children.empty() || !b.children.empty())
        continue;
      int like = 0, near = 0;
      for (std::size_t k = 0; k < a.assignment.size() && k < b.assignment.size(); ++k) {
        if (a.assignment[k] < 0 || b.assignment[k] < 0) continue;
        const Segment &p = segments.at(std::size_t(a.assignment[k])), &q = segments.at(std::size_t(b.assignment[k]));
        ++like;
        near += (p.origin() - q.origin()).norm() <= 1.25 * std::max(p.extent(), q.extent());
      }
      if (like > 1 && near == like) out.same_place.push_back({int(i), int(j)});
    }
  return out;
}

}  // namespace mereo::matching
