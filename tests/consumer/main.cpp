// Reads a frame through the installed mereo library, prints what it holds, and runs a small
// graph over it (the library's node kinds registered first, as README shows).
#include <cmath>
#include <cstdio>

#include <mereo/extension/projection.hpp>
#include <mereo/graph/graph.hpp>
#include <mereo/io/io.hpp>
#include <mereo/nodes/builtin.hpp>

int main(int argc, char** argv) {
  const char* input = argc > 1 ? argv[1] : "synthetic:0";
  const mereo::Frame frame = mereo::io::read(input);
  const mereo::Cloud cloud = mereo::extension::back_project(frame);
  std::size_t valid = 0;
  for (std::size_t i = 0; i < cloud.pixels(); ++i) valid += std::isfinite(cloud.data()[3 * i + 2]);
  std::printf("%s: %dx%d, %zu valid points\n", input, frame.cols(), frame.rows(), valid);

  mereo::nodes::register_builtin();
  auto g = mereo::graph::Graph::parse(
      "nodes: [{name: source, kind: frame_source}, {name: cloud, kind: back_project}]\n"
      "edges: [source.frame -> cloud.frame]\n");
  mereo::graph::RunOptions run;
  run.mode = mereo::graph::Mode::Parallel;
  const auto results = g.run_all(mereo::graph::FrameSource::recorded({frame, frame}), run);
  bool same = results.size() == 2;
  for (const auto& r : results) {
    const auto& c = r.outputs.at("cloud.cloud").get<mereo::Cloud>();
    for (std::size_t i = 0; same && i < c.size(); ++i)
      same = c.data()[i] == cloud.data()[i] || (std::isnan(c.data()[i]) && std::isnan(cloud.data()[i]));
  }
  std::printf("graph: %zu frames, clouds %s\n", results.size(), same ? "as back_project gives" : "DIFFER");
  return valid > 0 && same ? 0 : 1;
}
