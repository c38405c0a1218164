// bench_matching: matching object models to 20, 50, 100 and 200 primitives, by exhaustive search
// (eq. 5.6), by mereo's branch-and-bound (match.hpp) and by toulbar2 (Debian's weighted-CSP
// solver, run as a program on the same instance written in its .wcsp format), in one run.
//
// Instances: "rendered" (the primitives of the renderer's ground truth: cylinders, tori,
// spheres of several scenes side by side) and "adversarial" (many near-identical cylinders and
// tori, every body with a handle-like torus next to it, so that bounds are loose). Models: the
// mug of graphs/models/tabletop.yaml (2 parts) and a stool (a top and four interchangeable
// legs, 5 parts). Figures per case: nodes expanded and milliseconds for exhaustive search
// (counted without scoring where running it would take too long) and for the branch-and-bound
// with N = 10, and toulbar2's optimum (N = 1) and time; mereo's best score must be toulbar2's
// optimum. The last line is one JSON object.
//
//   bench_matching            every size, 3 repetitions
//   bench_matching --quick    sizes 20 and 50 (ctest)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "bench_util.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "mereo/matching/match.hpp"
#include "mereo/synthetic/scene.hpp"

namespace fs = std::filesystem;
using namespace mereo;
using namespace mereo::knowledge;
using namespace mereo::matching;
using bench::median;
using bench::now_ms;

namespace {

const char* kStool = R"(
concepts:
  - name: stool
    parts:
      - {role: top, class: cylinder}
      - {role: leg1, class: cylinder, group: legs}
      - {role: leg2, class: cylinder, group: legs}
      - {role: leg3, class: cylinder, group: legs}
      - {role: leg4, class: cylinder, group: legs}
    attributes:
      - {part: top, attribute: radius, range: [0.12, 0.2], margin: 0.02}
      - {part: top, attribute: height, at_most: 0.05, margin: 0.02}
      - {part: leg1, attribute: radius, range: [0.01, 0.03], margin: 0.005}
      - {part: leg2, attribute: radius, range: [0.01, 0.03], margin: 0.005}
      - {part: leg3, attribute: radius, range: [0.01, 0.03], margin: 0.005}
      - {part: leg4, attribute: radius, range: [0.01, 0.03], margin: 0.005}
    constraints:
      - {predicate: distance, parts: [top, leg1], min: 0.1, max: 0.3, margin: 0.05}
      - {predicate: distance, parts: [top, leg2], min: 0.1, max: 0.3, margin: 0.05}
      - {predicate: distance, parts: [top, leg3], min: 0.1, max: 0.3, margin: 0.05}
      - {predicate: distance, parts: [top, leg4], min: 0.1, max: 0.3, margin: 0.05}
      - {predicate: parallel, parts: [leg1, leg2]}
      - {predicate: parallel, parts: [leg3, leg4]}
      - {predicate: same_size, parts: [leg1, leg4], ratio: 0.9}
)";

Segment make(PrimitiveClass cls, Eigen::Vector3d p, Eigen::Vector3d axis, double r, double h, double minor = 0) {
  Segment s(cls.make());  // each class takes the fields it has (set_field's common names)
  s.set_field("point", p), s.set_field("axis", Eigen::Vector3d(axis.normalized())), s.set_field("radius", r);
  s.set_field("height", h), s.set_field("minor_radius", minor);
  return s;
}

/// The ground-truth primitives of rendered scenes, side by side (1.5 m apart), until n.
std::vector<Segment> rendered(int n) {
  std::vector<Segment> out;
  for (std::uint64_t seed = 700; int(out.size()) < n; ++seed) {
    const auto sf = synthetic::render(seed);
    const Eigen::Vector3d shift(1.5 * double(seed - 700), 0, 0);
    for (const auto& obj : sf.truth.objects_truth)
      for (const auto& part : obj.parts) {
        const auto& s = part.world;  // world frame: z up
        if ((s.cls != "cylinder" && s.cls != "torus" && s.cls != "sphere") || obj.model == "table") continue;
        if (int(out.size()) == n) break;
        out.push_back(make(primitive_class(s.cls), s.point + shift, s.axis, s.radius, s.height, s.minor_radius));
      }
  }
  return out;
}

/// Near-identical bodies with handle-like tori beside them, and legs around tops: loose bounds.
std::vector<Segment> adversarial(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const Eigen::Vector3d up(0, 0, 1);
  std::vector<Segment> out;
  while (int(out.size()) < n) {
    const Eigen::Vector3d c(0.4 * U(rng), 0.4 * U(rng), 0.05 + 0.01 * U(rng));
    const double r = 0.042 + 0.003 * U(rng);
    out.push_back(make(PrimitiveClass::of<shapes::Cylinder>(), c, up + 0.02 * Eigen::Vector3d(U(rng), U(rng), 0), r, 0.1));
    const double a = 0.025 + 0.002 * U(rng);
    const Eigen::Vector3d dir = Eigen::Vector3d(U(rng), U(rng), 0).normalized();
    out.push_back(make(PrimitiveClass::of<shapes::Torus>(), c + dir * (r + 0.6 * a), dir.cross(up), a, 0, 0.006));
    if (int(out.size()) + 2 <= n) {  // a stool top and a leg near it
      out.push_back(make(PrimitiveClass::of<shapes::Cylinder>(), c + Eigen::Vector3d(0, 0, 0.3), up, 0.16 + 0.01 * U(rng), 0.03));
      out.push_back(make(PrimitiveClass::of<shapes::Cylinder>(), c + Eigen::Vector3d(0.15 * U(rng), 0.15 * U(rng), 0), up,
                         0.02 + 0.002 * U(rng), 0.4));
    }
  }
  out.resize(n);
  return out;
}

/// Nodes of the exhaustive search tree (as match_exhaustive visits them), counted without scoring,
/// up to `cap` (beyond, the count is a lower bound and the branch-and-bound share an upper bound).
double count_exhaustive(const Concept& c, const std::vector<Segment>& segs, double cap, bool& capped) {
  const std::size_t P = c.parts.size();
  std::vector<std::vector<int>> domain(P);
  for (std::size_t i = 0; i < P; ++i)
    for (std::size_t j = 0; j < segs.size(); ++j)
      if (segs[j].class_name() == c.parts[i].cls) domain[i].push_back(int(j));
  std::vector<int> a(P, -2);
  std::vector<char> used(segs.size(), 0);
  double nodes = 0;
  capped = false;
  std::function<void(std::size_t)> rec = [&](std::size_t i) {
    nodes += 1;
    if (nodes >= cap) capped = true;
    if (i == P || capped) return;
    for (int s : domain[i]) {
      if (used[s]) continue;
      // the group order of match.cpp (increasing segments within a group)
      bool ok = true;
      for (std::size_t j = 0; j < i; ++j)
        if (!c.parts[i].group.empty() && c.parts[j].group == c.parts[i].group && a[j] >= s) ok = false;
      if (!ok) continue;
      used[s] = 1, a[i] = s;
      rec(i + 1);
      used[s] = 0;
    }
    if (c.parts[i].optional) {
      a[i] = -1;
      rec(i + 1);
    }
    a[i] = -2;
  };
  rec(0);
  return nodes;
}

long cost_of(double score) { return score > 0 ? std::lround(-std::log(score) * 1e6) : -1; }

/// toulbar2 on the instance (N = 1): parts are variables, segments of the part's class their
/// values (plus "missing" for optional parts); unary costs -log(membership), binary costs
/// -log(constraint) for two-part constraints, hard all-different and group order. Returns the
/// optimum cost (-1 if none or no solver) and the solver's time in ms.
std::pair<long, double> toulbar2(const Concept& c, const std::vector<Segment>& segs, const Context& ctx,
                                 const fs::path& dir) {
  const long top = 1000000000000L;  // hard
  const std::size_t P = c.parts.size();
  std::vector<std::vector<int>> dom(P);
  for (std::size_t i = 0; i < P; ++i) {
    for (std::size_t j = 0; j < segs.size(); ++j)
      if (segs[j].class_name() == c.parts[i].cls) dom[i].push_back(int(j));
    if (c.parts[i].optional) dom[i].push_back(-1);
    if (dom[i].empty()) return {-1, 0.0};
  }
  auto cost = [&](double v) { return v > 0 ? std::min(top, std::lround(-std::log(v) * 1e6)) : top; };
  std::ostringstream body;
  int functions = 0;
  for (std::size_t i = 0; i < P; ++i) {
    body << "1 " << i << " 0 " << dom[i].size() << "\n";
    for (std::size_t k = 0; k < dom[i].size(); ++k) {
      const int s = dom[i][k];
      body << k << " " << (s >= 0 ? cost(part_score(c, int(i), segs[s], ctx)) : cost(c.parts[i].missing_score)) << "\n";
    }
    ++functions;
  }
  std::vector<const Segment*> args(2);
  for (std::size_t i = 0; i < P; ++i)
    for (std::size_t j = i + 1; j < P; ++j) {
      // constraints between i and j, all-different, group order: one table
      std::vector<int> ks;
      for (std::size_t k = 0; k < c.constraints.size(); ++k) {
        const auto& r = c.constraints[k].parts;
        if (r.size() == 2 && ((c.part_index(r[0]) == int(i) && c.part_index(r[1]) == int(j)) ||
                              (c.part_index(r[0]) == int(j) && c.part_index(r[1]) == int(i))))
          ks.push_back(int(k));
      }
      const bool same_class = c.parts[i].cls == c.parts[j].cls;
      const bool group = !c.parts[i].group.empty() && c.parts[i].group == c.parts[j].group;
      if (ks.empty() && !same_class) continue;
      std::ostringstream t;
      int tuples = 0;
      for (std::size_t x = 0; x < dom[i].size(); ++x)
        for (std::size_t y = 0; y < dom[j].size(); ++y) {
          const int s = dom[i][x], u = dom[j][y];
          long w = 0;
          if (s >= 0 && s == u) w = top;
          if (group && ((s == -1 && u != -1) || (s >= 0 && u >= 0 && s >= u))) w = top;
          if (w < top && s >= 0 && u >= 0)
            for (int k : ks) {
              const auto& r = c.constraints[k].parts;
              args[0] = &segs[c.part_index(r[0]) == int(i) ? s : u];
              args[1] = &segs[c.part_index(r[0]) == int(i) ? u : s];
              w = std::min(top, w + cost(evaluate(c.constraints[k], args, ctx)));
            }
          if (w == 0) continue;
          t << x << " " << y << " " << w << "\n";
          ++tuples;
        }
      body << "2 " << i << " " << j << " 0 " << tuples << "\n" << t.str();
      ++functions;
    }
  std::size_t maxdom = 0;
  for (const auto& d : dom) maxdom = std::max(maxdom, d.size());
  const fs::path file = dir / "instance.wcsp";
  {
    std::ofstream out(file);
    out << "mereo " << P << " " << maxdom << " " << functions << " " << top << "\n";
    for (std::size_t i = 0; i < P; ++i) out << dom[i].size() << (i + 1 < P ? " " : "\n");
    out << body.str();
  }
  const fs::path log = dir / "toulbar2.log";
  const std::string cmd = "toulbar2 " + file.string() + " > " + log.string() + " 2>&1";
  if (std::system(cmd.c_str()) != 0) return {-1, NAN};
  std::ifstream in(log);
  std::string line;
  long optimum = -1;
  double seconds = NAN;
  while (std::getline(in, line)) {
    const auto p = line.find("Optimum: ");
    if (p == std::string::npos) continue;
    std::sscanf(line.c_str() + p, "Optimum: %ld", &optimum);
    const auto q = line.find(" and ", line.find("nodes"));
    if (q != std::string::npos) std::sscanf(line.c_str() + q, " and %lf seconds", &seconds);
  }
  return {optimum, seconds * 1000.0};
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--quick") quick = true;
  const std::vector<int> sizes = quick ? std::vector<int>{20, 50} : std::vector<int>{20, 50, 100, 200};
  // (exhaustive search runs where its tree has fewer than 3e6 nodes, 1e5 in quick mode; beyond,
  // its nodes are counted without scoring)
  const int repeats = quick ? 1 : 3;
  KnowledgeBase kb;
  load_models(kb, std::string(MEREO_SOURCE_DIR) + "/graphs/models/tabletop.yaml");
  parse_models(kb, kStool, "stool");
  const bool have_toulbar2 = std::system("command -v toulbar2 > /dev/null 2>&1") == 0;
  const fs::path dir = fs::temp_directory_path() / ("mereo_bench_matching_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  MatchOptions o;
  o.best = 10;
  o.context.up = Eigen::Vector3d::UnitZ();  // both kinds of instances are in a z-up frame

  std::printf("bench_matching: N = %d, %d repetitions, toulbar2 %s\n\n", o.best, repeats,
              have_toulbar2 ? "found" : "NOT FOUND (skipped)");
  std::printf("%-6s %-12s %5s %14s %10s %10s %9s %10s %10s %8s\n", "model", "instances", "n", "exh_nodes",
              "exh_ms", "bb_nodes", "bb_share", "bb_ms", "tb2_ms", "same_opt");
  nlohmann::json rows = nlohmann::json::array();
  for (const char* model : {"mug", "stool"}) {
    const Concept c = select(kb.resolve(model));
    for (const char* kind : {"rendered", "adversarial"}) {
      for (int n : sizes) {
        const auto segs = std::string(kind) == "rendered" ? rendered(n) : adversarial(n, 42);
        bool capped = false;
        const double exh_nodes = count_exhaustive(c, segs, 2e8, capped);
        double exh_ms = NAN;
        std::vector<Hypothesis> ex;
        if (exh_nodes < (quick ? 1e5 : 3e6)) {
          std::vector<double> t;
          for (int r = 0; r < repeats; ++r) {
            const double t0 = now_ms();
            ex = match_exhaustive(c, segs, o);
            t.push_back(now_ms() - t0);
          }
          exh_ms = median(t);
        }
        std::vector<double> t;
        MatchStats st;
        std::vector<Hypothesis> bb;
        for (int r = 0; r < repeats; ++r) {
          const double t0 = now_ms();
          bb = match(c, segs, o, &st);
          t.push_back(now_ms() - t0);
        }
        const double bb_ms = median(t);
        bool same_as_exhaustive = true;
        if (!std::isnan(exh_ms)) {
          same_as_exhaustive = ex.size() == bb.size();
          for (std::size_t i = 0; same_as_exhaustive && i < ex.size(); ++i)
            same_as_exhaustive = ex[i].assignment == bb[i].assignment && ex[i].score == bb[i].score;
        }
        long tb2 = -1;
        double tb2_ms = NAN;
        if (have_toulbar2) std::tie(tb2, tb2_ms) = toulbar2(c, segs, o.context, dir);
        const long ours = bb.empty() ? -1 : cost_of(bb.front().score);
        // toulbar2's costs are rounded per term: equal optimum up to that rounding
        const bool same_opt = !have_toulbar2 || (tb2 < 0 && ours < 0) || (tb2 >= 0 && std::labs(tb2 - ours) <= 20);
        const double share = double(st.expanded) / exh_nodes;
        std::printf("%-6s %-12s %5d %s%13.0f %10.2f %10zu %8.4f%% %10.3f %10.2f %8s%s\n", model, kind, n,
                    capped ? ">" : " ", exh_nodes,
                    exh_ms, st.expanded, 100 * share, bb_ms, tb2_ms, same_opt ? "yes" : "NO",
                    same_as_exhaustive ? "" : "  (differs from exhaustive!)");
        rows.push_back({{"model", model}, {"instances", kind}, {"n", n}, {"exhaustive_nodes", exh_nodes},
                        {"exhaustive_nodes_is_lower_bound", capped},
                        {"exhaustive_ms", std::isnan(exh_ms) ? nlohmann::json(nullptr) : nlohmann::json(exh_ms)},
                        {"bb_nodes", st.expanded}, {"bb_pruned", st.pruned}, {"bb_node_share", share},
                        {"bb_ms", bb_ms}, {"same_as_exhaustive", same_as_exhaustive},
                        {"toulbar2_ms", std::isnan(tb2_ms) ? nlohmann::json(nullptr) : nlohmann::json(tb2_ms)},
                        {"toulbar2_optimum", tb2}, {"mereo_best_cost", ours}, {"same_optimum", same_opt}});
      }
    }
  }
  fs::remove_all(dir);
  // the target: at 100 primitives and N = 10, at most 0.1% of the exhaustive nodes and 2 ms
  nlohmann::json target;
  for (const auto& r : rows)
    if (r["n"] == 100 && r["model"] == "stool")
      target[r["instances"].get<std::string>()] = {{"bb_node_share", r["bb_node_share"]}, {"bb_ms", r["bb_ms"]}};
  std::printf("%s\n", nlohmann::json({{"bench", "matching"}, {"quick", quick}, {"best", o.best},
                                      {"target_100_stool", target}, {"rows", rows}})
                          .dump()
                          .c_str());
  return 0;
}
