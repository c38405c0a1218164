// The library's node kinds and port types in the engine: what register_builtin() registers,
// the shipped graph files (and how they extend one another), the models node's checks, and the
// built-in nodes in both execution modes.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <thread>

#include "mereo/graph/graph.hpp"
#include "mereo/nodes/builtin.hpp"
#include "mereo/synthetic/scene.hpp"

using namespace mereo;
using namespace mereo::graph;

namespace {

std::vector<std::string> kinds() {
  std::vector<std::string> out;
  for (const auto& s : node_specs()) out.push_back(s.kind);
  return out;
}

}  // namespace

TEST(Builtin, RegistersTheListedKindsAndTypesOnce) {
  // The tests' main registered them already; more calls, also concurrent ones, change nothing.
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i) threads.emplace_back([] { nodes::register_builtin(); });
  for (auto& t : threads) t.join();
  EXPECT_EQ(kinds(), (std::vector<std::string>{"frame_source", "filter_depth", "back_project", "estimate_normals",
                                               "support_plane", "detect_primitives", "detect_edges", "find_regions", "detect_patches", "detect_legs", "models", "match_models",
                                               "interpret", "odometry", "track_objects", "report"}));  // no test-only kinds
  EXPECT_EQ(type_names(), (std::vector<std::string>{"Cloud", "Color", "Depth", "Frame", "Interpretation", "Labels",
                                                    "Lattice", "Mask", "ModelSet", "NormalMap", "Number", "Segments",
                                                    "SupportPlane", "Text", "Tracks"}));
  EXPECT_EQ(type_of<Frame>().name, "Frame");
  EXPECT_EQ(type_of<Cloud>().name, "Cloud");  // the first of the names of Image<float, 3>
  EXPECT_EQ(Value::make(Cloud(2, 3, 0.0f)).as(*find_type("NormalMap")).describe(), "3x2 normal map, 100% valid");
}

TEST(Builtin, EveryShippedGraphLoadsAndVerifies) {
  int loaded = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(MEREO_SOURCE_DIR) + "/graphs"))
    if (e.path().extension() == ".yaml") {
      EXPECT_NO_THROW(Graph::load(e.path().string())) << e.path();
      ++loaded;
    }
  EXPECT_GT(loaded, 0);
}

TEST(Builtin, ShippedTabletopGraphsExtendOneAnother) {
  const std::string dir = std::string(MEREO_SOURCE_DIR) + "/graphs/";
  const Graph base = Graph::load(dir + "tabletop.yaml");
  const Graph tracking = Graph::load(dir + "tabletop_tracking.yaml");
  const Graph odometry = Graph::load(dir + "tabletop_odometry.yaml");
  EXPECT_EQ(tracking.nodes().size(), base.nodes().size() + 1);
  EXPECT_EQ(odometry.nodes().size(), tracking.nodes().size() + 1);
  EXPECT_EQ(odometry.node("models").file, base.node("models").file);  // the models in one place
  auto feeds = [](const Graph& g, const std::string& to) {
    for (const auto& e : g.edges())
      if (e.to_node + "." + e.to_port == to) return e.from_node + "." + e.from_port;
    return std::string();
  };
  EXPECT_EQ(feeds(tracking, "result.frame"), "source.frame");
  EXPECT_EQ(feeds(odometry, "result.frame"), "poses.frame");
  EXPECT_EQ(feeds(odometry, "tracks.frame"), "poses.frame");
  EXPECT_EQ(feeds(odometry, "tracks.objects"), "interpretation.objects");
  EXPECT_EQ(feeds(base, "primitives.unfiltered"), "raw_cloud.cloud");
}

TEST(Builtin, ModelsAreCheckedWhenTheGraphIsVerified) {
  try {
    Graph::parse("nodes:\n  - name: models\n    kind: models\n    options: {models: \"mug,teapot\"}\n", "m.yaml");
    FAIL() << "no error";
  } catch (const GraphError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("m.yaml:2: node 'models' (models): "), std::string::npos) << msg;
    EXPECT_NE(msg.find("teapot"), std::string::npos) << msg;
  }
}

TEST(Builtin, DanglingRequiredInputNamesNodeAndPort) {
  Graph g;
  g.add("frame_source", "source");
  g.add("back_project", "cloud");
  try {
    g.verify();
    FAIL() << "no error";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("node 'cloud' (back_project): required input port 'frame'"),
              std::string::npos)
        << e.what();
  }
}

TEST(Builtin, FramesThroughBackProjectAreIdenticalInBothModes) {
  synthetic::SceneOptions so;
  so.width = 320, so.height = 240;
  so.intrinsics = {262.5, 262.5, 159.5, 119.5};
  std::vector<Frame> frames;
  for (auto& sf : synthetic::render_sequence(11, 8, so)) frames.push_back(sf.frame);
  Graph g;
  g.add("frame_source", "source");
  g.add("back_project", "cloud");
  g.connect("source.frame", "cloud.frame");
  RunOptions det, par;
  par.mode = Mode::Parallel;
  const auto a = g.run_all(FrameSource::recorded(frames), det);
  const auto b = g.run_all(FrameSource::from_function(frames.size(), [&](std::size_t i) { return frames[i]; }), par);
  ASSERT_EQ(a.size(), frames.size());
  ASSERT_EQ(b.size(), frames.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].frame_id, frames[i].id);
    EXPECT_EQ(b[i].frame_id, frames[i].id);
    const auto& ca = a[i].outputs.at("cloud.cloud").get<Cloud>();
    const auto& cb = b[i].outputs.at("cloud.cloud").get<Cloud>();
    ASSERT_TRUE(ca.same_size(cb));
    EXPECT_EQ(std::memcmp(ca.data(), cb.data(), ca.size() * sizeof(float)), 0) << i;
  }
  EXPECT_EQ(a[0].outputs.at("cloud.cloud").describe().rfind("320x240 cloud, ", 0), 0u);
}
