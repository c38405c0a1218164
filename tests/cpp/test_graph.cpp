// The dataflow engine: verification errors, graph files, both execution modes, error
// policies, live sources with overflow policies.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "mereo/graph/graph.hpp"
#include "mereo/synthetic/scene.hpp"

using namespace mereo;
using namespace mereo::graph;

namespace {

template <typename Fn>
std::string error_of(Fn fn) {
  try {
    fn();
  } catch (const GraphError& e) {
    return e.what();
  }
  return "(no error)";
}

// source -> cloud (back_project), source -> work1/work2 (checksum)
Graph small_graph() {
  Graph g;
  g.add("frame_source", "source");
  g.add("back_project", "cloud");
  g.add("checksum", "work1", {{"rounds", 2LL}});
  g.add("checksum", "work2", {{"rounds", 3LL}});
  g.connect("source.frame", "cloud.frame");
  g.connect("source.frame", "work1.frame");
  g.connect("source.frame", "work2.frame");
  return g;
}

// Frames of the synthetic renderer, rendered once for all tests.
const std::vector<Frame>& sequence50() {
  static const std::vector<Frame> frames = [] {
    synthetic::SceneOptions o;
    o.width = 320, o.height = 240;
    o.intrinsics = {262.5, 262.5, 159.5, 119.5};
    std::vector<Frame> out;
    for (auto& sf : synthetic::render_sequence(11, 50, o)) out.push_back(sf.frame);
    return out;
  }();
  return frames;
}

bool same_cloud(const Cloud& a, const Cloud& b) {
  return a.same_size(b) && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

long rss_kb() {
  std::ifstream in("/proc/self/status");
  std::string key;
  long value = 0;
  while (in >> key) {
    if (key == "VmRSS:") {
      in >> value;
      return value;
    }
    std::string rest;
    std::getline(in, rest);
  }
  return 0;
}

}  // namespace

TEST(GraphVerify, DanglingRequiredInputNamesNodeAndPort) {
  Graph g;
  g.add("frame_source", "source");
  g.add("back_project", "cloud");
  const auto msg = error_of([&] { g.verify(); });
  EXPECT_NE(msg.find("node 'cloud'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("input port 'frame'"), std::string::npos) << msg;
}

TEST(GraphVerify, PortsTypesOptionsAndCycles) {
  {
    Graph g = small_graph();
    g.add("back_project", "bad");
    g.connect("cloud.cloud", "bad.frame");  // Cloud into a Frame input
    const auto msg = error_of([&] { g.verify(); });
    EXPECT_NE(msg.find("cloud.cloud is Cloud"), std::string::npos) << msg;
    EXPECT_NE(msg.find("bad.frame takes Frame"), std::string::npos) << msg;
  }
  {
    Graph g = small_graph();
    g.connect("source.frame", "work1.image");
    const auto msg = error_of([&] { g.verify(); });
    EXPECT_NE(msg.find("node 'work1' (checksum) has no input port 'image'"), std::string::npos) << msg;
  }
  {
    Graph g = small_graph();
    g.connect("source.frame", "cloud.frame");
    EXPECT_NE(error_of([&] { g.verify(); }).find("connected twice"), std::string::npos);
  }
  {
    Graph g;
    g.add("identity", "a");
    g.add("identity", "b");
    g.connect("a.frame", "b.frame");
    g.connect("b.frame", "a.frame");
    EXPECT_NE(error_of([&] { g.verify(); }).find("cycle through nodes: a, b"), std::string::npos);
  }
  Graph g;
  auto msg = error_of([&] { g.add("checksum", "w", {{"rounds", 0LL}}); });
  EXPECT_NE(msg.find("node 'w' (checksum): option 'rounds' = 0 is outside its range"), std::string::npos) << msg;
  msg = error_of([&] { g.add("checksum", "w", {{"round", 3LL}}); });
  EXPECT_NE(msg.find("option 'round' does not exist (options: rounds)"), std::string::npos) << msg;
  msg = error_of([&] { g.add("checksum", "w", {{"rounds", std::string("many")}}); });
  EXPECT_NE(msg.find("must be int"), std::string::npos) << msg;
  msg = error_of([&] { g.add("no_such_kind", "w"); });
  EXPECT_NE(msg.find("unknown node kind 'no_such_kind'"), std::string::npos) << msg;
}

TEST(GraphFile, ErrorsNameTheFileAndLine) {
  const std::string text =
      "nodes:\n"
      "  - name: source\n"
      "    kind: frame_source\n"
      "  - name: cloud\n"
      "    kind: back_project\n"
      "edges:\n"
      "  - source.frame -> cloud.frme\n";
  auto msg = error_of([&] { Graph::parse(text, "g.yaml"); });
  EXPECT_NE(msg.find("g.yaml:7: edge source.frame -> cloud.frme"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no input port 'frme'"), std::string::npos) << msg;
  msg = error_of([&] { Graph::parse("nodes:\n  - name: a\n    kind: checksum\n    options: {rounds: -2}\n", "h.yaml"); });
  EXPECT_NE(msg.find("h.yaml:2: node 'a' (checksum): option 'rounds' = -2"), std::string::npos) << msg;
  msg = error_of([&] { Graph::parse("nodes:\n  - name: a\n    kind: checksum\n", "d.yaml"); });
  EXPECT_NE(msg.find("d.yaml:2: node 'a' (checksum): required input port 'frame'"), std::string::npos) << msg;
  msg = error_of([&] { Graph::parse("nodes:\n  - name: a\n    kidn: checksum\n", "t.yaml"); });
  EXPECT_NE(msg.find("t.yaml:3: unknown field 'kidn'"), std::string::npos) << msg;
  msg = error_of([&] { Graph::parse("nodes: [\n", "y.yaml"); });
  EXPECT_NE(msg.find("y.yaml:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not valid YAML"), std::string::npos) << msg;
  msg = error_of([] { Graph::load("/no/such/graph.yaml"); });
  EXPECT_NE(msg.find("/no/such/graph.yaml: cannot open"), std::string::npos) << msg;
}

TEST(GraphFile, SaveLoadRoundTripAndShippedGraphs) {
  Graph g = small_graph();
  g.set_overflow(Overflow::KeepLatest, 1);
  const std::string text = g.to_yaml();
  Graph h = Graph::parse(text, "round.yaml");
  EXPECT_EQ(h.to_yaml(), text);
  EXPECT_EQ(h.node("work2").options.get_int("rounds"), 3);
  EXPECT_EQ(h.overflow(), Overflow::KeepLatest);
  // Every graph file shipped in graphs/ loads and verifies.
  int loaded = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(MEREO_SOURCE_DIR) + "/graphs"))
    if (e.path().extension() == ".yaml") {
      EXPECT_NO_THROW(Graph::load(e.path().string())) << e.path();
      ++loaded;
    }
  EXPECT_GT(loaded, 0);
  const std::string dot = g.to_dot();
  EXPECT_NE(dot.find("\"source\" -> \"work1\""), std::string::npos);
}

TEST(GraphRun, BothModesGiveIdenticalResultsOver50Frames) {
  const auto& frames = sequence50();
  Graph g = small_graph();
  RunOptions det;
  RunOptions par;
  par.mode = Mode::Parallel;
  par.max_in_flight = 4;
  const auto a = g.run_all(FrameSource::recorded(frames), det);
  const auto b = g.run_all(FrameSource::recorded(frames), par);
  ASSERT_EQ(a.size(), 50u);
  ASSERT_EQ(b.size(), 50u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].index, i);
    EXPECT_EQ(b[i].index, i);  // in frame order
    EXPECT_EQ(a[i].frame_id, b[i].frame_id);
    ASSERT_EQ(a[i].outputs.size(), 3u);
    EXPECT_EQ(a[i].outputs.at("work1.value").get<double>(), b[i].outputs.at("work1.value").get<double>());
    EXPECT_EQ(a[i].outputs.at("work2.value").get<double>(), b[i].outputs.at("work2.value").get<double>());
    EXPECT_TRUE(same_cloud(a[i].outputs.at("cloud.cloud").get<Cloud>(), b[i].outputs.at("cloud.cloud").get<Cloud>()));
  }
  // Different frames give different checksums (the outputs depend on the input).
  EXPECT_NE(a[0].outputs.at("work1.value").get<double>(), a[1].outputs.at("work1.value").get<double>());
  const auto& t = g.last_summary().timings;
  ASSERT_EQ(t.size(), 3u);
  for (const auto& n : t) {
    EXPECT_EQ(n.count, 50u);
    EXPECT_LE(n.median_ms, n.max_ms);
  }
}

TEST(GraphRun, NodeThrowingOnFrame7) {
  const auto& frames = sequence50();
  for (Mode mode : {Mode::Deterministic, Mode::Parallel}) {
    Graph g = small_graph();
    g.add("fail_on_frame", "broken", {{"frame", 7LL}});
    g.add("back_project", "after");
    g.connect("source.frame", "broken.frame");
    g.connect("broken.frame", "after.frame");
    RunOptions o;
    o.mode = mode;
    // Stop: the error names the node and frame 7; frames 0-6 were delivered.
    std::vector<std::size_t> delivered;
    try {
      g.run(FrameSource::recorded(frames), o, [&](FrameResult&& r) { delivered.push_back(r.index); });
      FAIL() << "no error";
    } catch (const NodeError& e) {
      EXPECT_EQ(e.node, "broken");
      EXPECT_EQ(e.frame_index, 7u);
      EXPECT_NE(std::string(e.what()).find("node 'broken' failed on frame 7"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("failing on purpose"), std::string::npos);
    }
    EXPECT_EQ(delivered, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6}));
    // Skip: every other frame completes.
    o.on_error = ErrorPolicy::Skip;
    RunSummary s;
    const auto results = g.run_all(FrameSource::recorded(frames), o, &s);
    ASSERT_EQ(results.size(), 50u);
    EXPECT_EQ(s.completed, 49u);
    EXPECT_EQ(s.failed, 1u);
    for (const auto& r : results) {
      EXPECT_EQ(r.ok(), r.index != 7) << r.index;
      if (r.ok()) EXPECT_TRUE(r.outputs.count("after.cloud"));
    }
    EXPECT_EQ(results[7].error->node, "broken");
  }
}

TEST(GraphRun, LiveKeepLatestBoundsMemoryAndCountsDrops) {
  const Frame base = sequence50()[0];
  Graph g;
  g.add("frame_source", "source");
  g.add("checksum", "slow", {{"rounds", 20LL}});
  g.connect("source.frame", "slow.frame");
  for (Mode mode : {Mode::Deterministic, Mode::Parallel}) {
    auto queue = std::make_shared<FrameQueue>(1, Overflow::KeepLatest);
    std::vector<long> rss;
    std::thread producer([&] {
      for (int i = 0; i < 1000; ++i) {
        Frame f = base;
        f.depth = base.depth.clone();  // a fresh buffer per frame, as a camera gives
        f.color = base.color.clone();
        f.id = std::to_string(i);
        queue->push(std::move(f));
        if (i % 50 == 0) rss.push_back(rss_kb());
      }
      queue->close();
    });
    RunOptions o;
    o.mode = mode;
    o.max_in_flight = 2;
    std::size_t processed = 0;
    const auto s = g.run(FrameSource::from_queue(queue), o, [&](FrameResult&&) { ++processed; });
    producer.join();
    EXPECT_EQ(queue->pushed(), 1000u);
    EXPECT_EQ(s.dropped, queue->dropped());
    EXPECT_EQ(s.dropped + processed, 1000u) << "every frame is either processed or counted as dropped";
    EXPECT_GT(s.dropped, 0u);
    // Memory stays flat: after the first samples, no growth beyond a few frames' worth.
    const long early = *std::max_element(rss.begin(), rss.begin() + 4);
    const long late = *std::max_element(rss.begin() + 4, rss.end());
    EXPECT_LT(late - early, 20 * 1024) << "RSS grew from " << early << " kB to " << late << " kB";
  }
}

TEST(GraphRun, TraceAndCustomNodes) {
  Graph g = small_graph();
  NodeSpec spec;
  spec.kind = "count_valid";
  spec.doc = "Counts valid depth pixels.";
  spec.inputs = {{"frame", "Frame", ""}};
  spec.outputs = {{"n", "Number", ""}};
  spec.make = [](const Options&) {
    return NodeBody([](NodeContext& ctx) {
      const auto& d = ctx.input<Frame>("frame").depth;
      double n = 0;
      for (std::size_t i = 0; i < d.pixels(); ++i) n += d.data()[i] > 0;
      ctx.output("n", n);
    });
  };
  g.add_custom(spec, "valid");
  g.connect("source.frame", "valid.frame");
  RunOptions o;
  o.mode = Mode::Parallel;
  o.trace = true;
  o.keep = {"valid.n"};
  std::vector<Frame> frames(sequence50().begin(), sequence50().begin() + 5);
  const auto r = g.run_all(FrameSource::recorded(frames), o);
  ASSERT_EQ(r.size(), 5u);
  EXPECT_EQ(r[0].outputs.size(), 1u);
  EXPECT_GT(r[0].outputs.at("valid.n").get<double>(), 1000);
  const auto trace = nlohmann::json::parse(g.trace_json());
  EXPECT_EQ(trace["traceEvents"].size(), 5u * 4u);
  EXPECT_EQ(trace["traceEvents"][0]["ph"], "X");
  EXPECT_THROW(g.to_yaml(), GraphError);  // a custom node cannot be saved
}
