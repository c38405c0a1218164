// mereo-run: runs a graph file over inputs, with no Python involved.
//
//   mereo-run GRAPH.yaml INPUT... [--mode parallel|deterministic] [--in-flight K]
//             [--on-error stop|skip] [--intrinsics fx,fy,cx,cy|FILE] [--depth-scale S]
//             [--frames N] [--trace FILE] [--result NODE.PORT]
//   mereo-run --list                 every node kind with its ports and options
//
// Prints one JSON line per frame (its id and a summary of each kept output), then per-node
// timings on stderr. With --result NODE.PORT (a report node's output) each line is that
// frame's result, as `mereo recognize` writes it, with "timing_ms" per node. Bad input: one line on stderr and exit status 2.
// A frame that fails (it cannot be read, or a node finds nothing usable in it) gets a line with
// its "error" and the run goes on (--on-error skip, the default, as `mereo recognize` does).
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mereo/core/error.hpp"
#include "mereo/core/parse.hpp"
#include "mereo/graph/graph.hpp"
#include "mereo/io/io.hpp"
#include "mereo/nodes/builtin.hpp"

using namespace mereo;

namespace {

int usage() {
  std::cerr << "usage: mereo-run GRAPH.yaml INPUT... [--mode parallel|deterministic] [--in-flight K]\n"
               "                 [--on-error stop|skip] [--intrinsics fx,fy,cx,cy|FILE] [--depth-scale S]\n"
               "                 [--frames N] [--trace FILE] [--result NODE.PORT]\n"
               "       mereo-run --list\n";
  return 2;
}

void list_kinds() {
  for (const auto& s : graph::node_specs()) {
    std::cout << s.kind << ": " << s.doc << "\n";
    for (const auto& p : s.inputs) std::cout << "  in  " << p.name << " (" << p.type << ") " << p.doc << "\n";
    for (const auto& p : s.outputs) std::cout << "  out " << p.name << " (" << p.type << ") " << p.doc << "\n";
    for (const auto& o : s.options) std::cout << "  option " << o.name << " (" << to_string(o.type) << ") " << o.doc << "\n";
  }
}

/// The value of `option` as a number (NaN and inf too: the reader that uses it checks its range),
/// or an InputError naming the option and value.
double number(const std::string& option, const std::string& text) {
  const auto x = parse_number(text);
  if (!x) throw InputError(option + " " + printable(text) + ": expected a number");
  return *x;
}

/// The value of `option` as a whole number in [lo, hi].
long whole(const std::string& option, const std::string& text, long lo, long hi) {
  const double x = number(option, text);
  if (!(x >= double(lo) && x <= double(hi)) || x != std::floor(x))
    throw InputError(option + " " + printable(text) + ": expected a whole number from " + std::to_string(lo) +
                     " to " + std::to_string(hi));
  return long(x);
}

}  // namespace

int main(int argc, char** argv) {
  nodes::register_builtin();
  std::vector<std::string> positional;
  graph::RunOptions run;
  run.mode = graph::Mode::Parallel;
  run.on_error = graph::ErrorPolicy::Skip;
  io::ReadOptions read;
  std::string trace, result;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc) throw InputError(a + ": missing value");
        return argv[++i];
      };
      if (a == "--list") {
        list_kinds();
        return 0;
      } else if (a == "--help" || a == "-h") {
        usage();
        return 0;
      } else if (a == "--mode") {
        const auto m = next();
        if (m != "parallel" && m != "deterministic") throw InputError("--mode " + m + ": not parallel or deterministic");
        run.mode = m == "parallel" ? graph::Mode::Parallel : graph::Mode::Deterministic;
      } else if (a == "--in-flight") {
        run.max_in_flight = std::size_t(whole(a, next(), 1, 1024));
      } else if (a == "--on-error") {
        const auto p = next();
        if (p != "stop" && p != "skip") throw InputError("--on-error " + p + ": not stop or skip");
        run.on_error = p == "skip" ? graph::ErrorPolicy::Skip : graph::ErrorPolicy::Stop;
      } else if (a == "--intrinsics") {
        read.intrinsics = io::read_intrinsics(next());
      } else if (a == "--depth-scale") {
        read.depth_scale = number(a, next());
      } else if (a == "--frames") {
        read.synthetic_frames = int(whole(a, next(), 1, 1000000));
      } else if (a == "--result") {
        result = next();
        run.keep.push_back(result);
      } else if (a == "--trace") {
        trace = next();
        run.trace = true;
      } else if (a.rfind("--", 0) == 0) {
        throw InputError("unknown option " + a);
      } else {
        positional.push_back(a);
      }
    }
    if (positional.size() < 2) return usage();
    graph::Graph g = graph::Graph::load(positional[0]);
    const io::Sequence seq = io::open({positional.begin() + 1, positional.end()}, read);
    const auto source = graph::FrameSource::from_function(seq.size(), [&](std::size_t i) { return seq.load(i); });
    const auto summary = g.run(source, run, [&](graph::FrameResult&& r) {
      const auto it = result.empty() ? r.outputs.end() : r.outputs.find(result);
      if (it != r.outputs.end() && it->second.type().name == "Text") {
        // the JSON result of a report node, with this frame's per-node times
        nlohmann::json line = nlohmann::json::parse(it->second.get<std::string>());
        double total = 0;
        for (const auto& [node, ms] : r.timings_ms) line["timing_ms"][node] = ms, total += ms;
        line["timing_ms"]["total"] = total;
        std::cout << line.dump() << std::endl;
        return;
      }
      nlohmann::json line = {{"frame", r.frame_id}, {"index", r.index}};
      for (const auto& [name, v] : r.outputs) line["outputs"][name] = v.describe();
      if (r.error) line["error"] = r.error->what();
      std::cout << line.dump() << std::endl;
    });
    std::fprintf(stderr, "%zu frames, %zu completed, %zu failed, %.1f ms\n", summary.frames, summary.completed,
                 summary.failed, summary.wall_ms);
    std::fprintf(stderr, "%-20s %7s %10s %10s %10s\n", "node", "count", "mean ms", "median ms", "max ms");
    for (const auto& t : summary.timings)
      std::fprintf(stderr, "%-20s %7zu %10.2f %10.2f %10.2f\n", t.node.c_str(), t.count, t.mean_ms, t.median_ms,
                   t.max_ms);
    if (!trace.empty()) g.write_trace(trace);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "mereo-run: error: " << e.what() << "\n";
    return 2;
  }
}
