// The dataflow engine alone (it links only the engine's objects): verification errors, graph
// files (and files that extend others), both execution modes, error policies, live sources with
// overflow policies, port types, node bodies made once per run, constant nodes. Its port types, source kind and scale_depth node are the tests' own; identity,
// checksum and fail_on_frame come from tests/support/test_nodes.hpp.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "mereo/graph/graph.hpp"
#include "support/test_nodes.hpp"

using namespace mereo::graph;

namespace {

// The tests' frame: an id and a depth image (values only; what checksum reads).
struct Depth {
  std::vector<float> values;
  const float* data() const { return values.data(); }
  std::size_t pixels() const { return values.size(); }
};
struct TestFrame {
  std::string id;
  Depth depth;
};

// The port types "Frame" and "Depth", a source kind and a node with an output of another type.
void register_test_kinds() {
  register_type<TestFrame>("Frame", [](const TestFrame& f) { return "frame " + f.id; });
  register_type<Depth>("Depth", [](const Depth& d) { return std::to_string(d.pixels()) + " depth values"; });
  NodeSpec source;
  source.kind = "frame_source";
  source.doc = "The run's frames.";
  source.outputs = {{"frame", "Frame", "the frame"}};
  source.is_source = true;
  source.make = [](const Options&) { return NodeBody([](NodeContext&) {}); };
  register_node(source);
  NodeSpec scale;
  scale.kind = "scale_depth";
  scale.doc = "The frame's depth times a factor.";
  scale.inputs = {{"frame", "Frame", "a frame"}};
  scale.outputs = {{"depth", "Depth", "the scaled depth"}};
  scale.options = {{"factor", OptionType::Double, 2.0, -1e3, 1e3, {}, "the factor"}};
  scale.make = [](const Options& o) {
    const double factor = o.get_double("factor");
    return NodeBody([factor](NodeContext& ctx) {
      Depth d = ctx.input<TestFrame>("frame").depth;
      for (auto& v : d.values) v = float(v * factor);
      ctx.output("depth", std::move(d));
    });
  };
  register_node(scale);
  mereo::test_nodes::register_test_nodes<TestFrame>();
}

template <typename Fn>
std::string error_of(Fn fn) {
  try {
    fn();
  } catch (const GraphError& e) {
    return e.what();
  }
  return "(no error)";
}

// source -> scaled (scale_depth), source -> work1/work2 (checksum)
Graph small_graph() {
  Graph g;
  g.add("frame_source", "source");
  g.add("scale_depth", "scaled");
  g.add("checksum", "work1", {{"rounds", 2LL}});
  g.add("checksum", "work2", {{"rounds", 3LL}});
  g.connect("source.frame", "scaled.frame");
  g.connect("source.frame", "work1.frame");
  g.connect("source.frame", "work2.frame");
  return g;
}

// A frame of rows x cols pseudo-random depths in [0.3, 3.3) m, a tenth of them missing (0).
TestFrame test_frame(int index, int rows = 240, int cols = 320) {
  TestFrame f;
  char id[16];
  std::snprintf(id, sizeof id, "%04d", index);
  f.id = id;
  f.depth.values.resize(std::size_t(rows) * cols);
  std::uint32_t x = 2463534242u + 7919u * std::uint32_t(index);
  for (auto& v : f.depth.values) {
    x ^= x << 13, x ^= x >> 17, x ^= x << 5;  // xorshift32
    v = x % 10 == 0 ? 0.0f : 0.3f + float(x % 30000) * 1e-4f;
  }
  return f;
}

const std::vector<TestFrame>& sequence50() {
  static const std::vector<TestFrame> frames = [] {
    std::vector<TestFrame> out;
    for (int i = 0; i < 50; ++i) out.push_back(test_frame(i));
    return out;
  }();
  return frames;
}

// Built with AddressSanitizer (scripts/asan.sh)? GCC defines __SANITIZE_ADDRESS__, Clang has
// __has_feature(address_sanitizer).
#if defined(__SANITIZE_ADDRESS__)
#define MEREO_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MEREO_TEST_ASAN 1
#endif
#endif

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
  g.add("scale_depth", "scaled");
  const auto msg = error_of([&] { g.verify(); });
  EXPECT_NE(msg.find("node 'scaled'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("input port 'frame'"), std::string::npos) << msg;
}

TEST(GraphVerify, PortsTypesOptionsAndCycles) {
  {
    Graph g = small_graph();
    g.add("scale_depth", "bad");
    g.connect("scaled.depth", "bad.frame");  // Depth into a Frame input
    const auto msg = error_of([&] { g.verify(); });
    EXPECT_NE(msg.find("scaled.depth is Depth"), std::string::npos) << msg;
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
    g.connect("source.frame", "scaled.frame");
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
      "  - name: scaled\n"
      "    kind: scale_depth\n"
      "edges:\n"
      "  - source.frame -> scaled.frme\n";
  auto msg = error_of([&] { Graph::parse(text, "g.yaml"); });
  EXPECT_NE(msg.find("g.yaml:7: edge source.frame -> scaled.frme"), std::string::npos) << msg;
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

TEST(GraphFile, SaveLoadRoundTrip) {
  Graph g = small_graph();
  g.set_overflow(Overflow::KeepLatest, 1);
  g.set_options("scaled", {{"factor", 3LL}});  // an integer where a real is wanted
  const std::string text = g.to_yaml();
  Graph h = Graph::parse(text, "round.yaml");
  EXPECT_EQ(h.to_yaml(), text);
  EXPECT_EQ(h.node("work2").options.get_int("rounds"), 3);
  EXPECT_EQ(h.node("scaled").options.get_double("factor"), 3.0);
  EXPECT_EQ(h.overflow(), Overflow::KeepLatest);
  const auto path = std::filesystem::temp_directory_path() / ("mereo_test_graph_" + std::to_string(::getpid()) + ".yaml");
  g.save(path.string());
  EXPECT_EQ(Graph::load(path.string()).to_yaml(), text);
  std::filesystem::remove(path);
  const std::string dot = g.to_dot();
  EXPECT_NE(dot.find("\"source\" -> \"work1\""), std::string::npos);
}

namespace {

// A folder of graph files for one test, removed afterwards.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("mereo_test_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return (path / name).string();
  }
};

const char* kBase =
    "name: base\n"
    "nodes:\n"
    "  - name: source\n"
    "    kind: frame_source\n"
    "  - name: scaled\n"
    "    kind: scale_depth\n"
    "  - name: work\n"
    "    kind: checksum\n"
    "    options: {rounds: 2}\n"
    "edges:\n"
    "  - source.frame -> scaled.frame\n"
    "  - source.frame -> work.frame\n";

}  // namespace

TEST(GraphFile, ExtendsTakesTheBaseThenOverridesAndAdds) {
  TempDir dir("extends");
  dir.write("base.yaml", kBase);
  std::filesystem::create_directories(dir.path / "more");
  // a path relative to the file; an option override; a new node; an edge that replaces the base's
  // edge into work.frame, and a new one
  const std::string derived = dir.write("more/derived.yaml",
                                        "extends: ../base.yaml\n"
                                        "nodes:\n"
                                        "  - name: work\n"
                                        "    options: {rounds: 5}\n"
                                        "  - name: gate\n"
                                        "    kind: identity\n"
                                        "edges:\n"
                                        "  - source.frame -> gate.frame\n"
                                        "  - gate.frame -> work.frame\n");
  Graph g = Graph::load(derived);
  std::vector<std::string> names;
  for (const auto& n : g.nodes()) names.push_back(n.name);
  EXPECT_EQ(names, (std::vector<std::string>{"source", "scaled", "work", "gate"}));
  EXPECT_EQ(g.node("work").options.get_int("rounds"), 5);
  EXPECT_EQ(g.node("scaled").file, (dir.path / "more/../base.yaml").string());
  EXPECT_EQ(g.node("gate").file, derived);
  EXPECT_EQ(g.node("gate").line, 5);
  ASSERT_EQ(g.edges().size(), 3u);
  EXPECT_EQ(g.edges()[1].from_node, "gate");  // in the place of the base's source.frame -> work.frame
  EXPECT_EQ(g.edges()[1].to_node, "work");
  EXPECT_EQ(g.edges()[2].to_node, "gate");
  // saved self-contained: the same graph without the base file
  const std::string text = g.to_yaml();
  EXPECT_EQ(text.find("extends"), std::string::npos);
  std::filesystem::remove(dir.path / "base.yaml");
  Graph h = Graph::parse(text, "saved.yaml");
  EXPECT_EQ(h.to_yaml(), text);
  EXPECT_EQ(h.node("work").options.get_int("rounds"), 5);
  EXPECT_NE(error_of([&] { Graph::load(derived); }).find("derived.yaml:1: cannot open the graph file"), std::string::npos);
}

TEST(GraphFile, ExtendsErrorsNameTheFileAndLine) {
  TempDir dir("extends_errors");
  dir.write("base.yaml", kBase);
  // an override that changes the kind
  auto msg = error_of([&] {
    Graph::load(dir.write("kind.yaml", "extends: base.yaml\nnodes:\n  - name: work\n    kind: identity\n"));
  });
  EXPECT_NE(msg.find("kind.yaml:4: node 'work' is a checksum in "), std::string::npos) << msg;
  EXPECT_NE(msg.find("base.yaml:7: "), std::string::npos) << msg;
  // a bad option value in an override
  msg = error_of([&] {
    Graph::load(dir.write("option.yaml", "extends: base.yaml\nnodes:\n  - name: work\n    options: {rounds: 0}\n"));
  });
  EXPECT_NE(msg.find("option.yaml:3: node 'work' (checksum): option 'rounds' = 0 is outside its range"), std::string::npos)
      << msg;
  // an edge of the derived file that names a port that does not exist: its own file and line
  msg = error_of([&] { Graph::load(dir.write("edge.yaml", "extends: base.yaml\nedges:\n  - scaled.depth -> work.depth\n")); });
  EXPECT_NE(msg.find("edge.yaml:3: edge scaled.depth -> work.depth"), std::string::npos) << msg;
  // an error in the base names the base's line and the file that extends it
  dir.write("broken.yaml", "nodes:\n  - name: a\n    kind: checksum\n    options: {rounds: -1}\n");
  msg = error_of([&] { Graph::load(dir.write("on_broken.yaml", "# a comment\nextends: broken.yaml\n")); });
  EXPECT_NE(msg.find("broken.yaml:2: node 'a' (checksum): option 'rounds' = -1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(in the graph extended by " + (dir.path / "on_broken.yaml").string() + ":2)"), std::string::npos)
      << msg;
  // a cycle of files
  dir.write("a.yaml", "extends: b.yaml\n");
  dir.write("b.yaml", "extends: a.yaml\n");
  msg = error_of([&] { Graph::load((dir.path / "a.yaml").string()); });
  EXPECT_NE(msg.find("b.yaml:1: 'extends' makes a cycle"), std::string::npos) << msg;
  // a base node overridden twice in one file
  msg = error_of([&] {
    Graph::load(dir.write("twice.yaml", "extends: base.yaml\nnodes:\n  - name: work\n  - name: work\n"));
  });
  EXPECT_NE(msg.find("twice.yaml:4: node 'work' is defined twice"), std::string::npos) << msg;
}

namespace {

std::atomic<int> made{0}, ran{0};

// A constant node whose making and running are counted, and a node that reads it (graph-local
// kinds: the registered list stays the tests' own).
NodeSpec counted_constant() {
  NodeSpec c;
  c.kind = "counted_constant";
  c.outputs = {{"value", "Number", ""}};
  c.options = {{"value", OptionType::Double, 3.0, 0, 100, {}, ""}};
  c.constant = true;
  c.make = [](const Options& o) {
    ++made;
    const double v = o.get_double("value");
    return NodeBody([v](NodeContext& ctx) {
      ++ran;
      ctx.output("value", v);
    });
  };
  return c;
}

NodeSpec counted_use() {
  NodeSpec u;
  u.kind = "counted_use";
  u.inputs = {{"frame", "Frame", ""}, {"value", "Number", ""}};
  u.outputs = {{"value", "Number", ""}};
  u.make = [](const Options&) {
    ++made;
    return NodeBody([](NodeContext& ctx) { ctx.output("value", ctx.input<double>("value") + double(ctx.frame_index())); });
  };
  return u;
}

}  // namespace

TEST(GraphRun, BodiesAreMadeOncePerRunAndConstantNodesRunOnce) {
  Graph g;
  g.add("frame_source", "source");
  g.add_custom(counted_constant(), "k");
  g.add_custom(counted_use(), "use");
  g.connect("source.frame", "use.frame");
  g.connect("k.value", "use.value");
  made = 0, ran = 0;
  g.verify();
  EXPECT_EQ(made, 2);
  g.verify();
  EXPECT_EQ(made, 2);  // kept for the next run
  std::vector<TestFrame> frames(sequence50().begin(), sequence50().begin() + 6);
  for (Mode mode : {Mode::Deterministic, Mode::Parallel}) {
    made = 0, ran = 0;
    RunOptions o;
    o.mode = mode;
    o.keep = {"use.value", "k.value"};
    const auto r = g.run_all(FrameSource::recorded(frames), o);
    EXPECT_EQ(made, mode == Mode::Deterministic ? 0 : 2);  // the second run makes fresh bodies
    EXPECT_EQ(ran, 1);  // the constant node ran once, before the frames
    ASSERT_EQ(r.size(), 6u);
    for (std::size_t i = 0; i < r.size(); ++i) {
      EXPECT_EQ(r[i].outputs.at("use.value").get<double>(), 3.0 + double(i));
      EXPECT_EQ(r[i].outputs.at("k.value").get<double>(), 3.0);  // every frame has it
      EXPECT_FALSE(r[i].timings_ms.count("k"));                  // not a per-frame node
    }
  }
  // new options: that node's body is made again, the others' are kept
  g.verify();
  made = 0;
  g.set_options("k", {{"value", 4.0}});
  g.verify();
  EXPECT_EQ(made, 1);
  RunOptions o;
  o.keep = {"use.value"};
  EXPECT_EQ(g.run_all(FrameSource::recorded(frames), o)[0].outputs.at("use.value").get<double>(), 4.0);
  EXPECT_EQ(made, 1);
  // what a body rejects when it is made fails verify(), naming the node
  NodeSpec picky = counted_constant();
  picky.kind = "picky";
  picky.make = [](const Options&) -> NodeBody { throw std::invalid_argument("option 'value': not today"); };
  g.add_custom(picky, "p");
  EXPECT_NE(error_of([&] { g.verify(); }).find("node 'p' (picky): option 'value': not today"), std::string::npos);
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
    const auto& da = a[i].outputs.at("scaled.depth").get<Depth>().values;
    EXPECT_EQ(da, b[i].outputs.at("scaled.depth").get<Depth>().values);
    EXPECT_EQ(da[1], 2 * frames[i].depth.values[1]);
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
    g.add("scale_depth", "after");
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
      if (r.ok()) EXPECT_TRUE(r.outputs.count("after.depth"));
    }
    EXPECT_EQ(results[7].error->node, "broken");
  }
}

TEST(GraphRun, LiveKeepLatestBoundsMemoryAndCountsDrops) {
  const TestFrame base = test_frame(0, 480, 640);
  Graph g;
  g.add("frame_source", "source");
  g.add("checksum", "slow", {{"rounds", 20LL}});
  g.connect("source.frame", "slow.frame");
  for (Mode mode : {Mode::Deterministic, Mode::Parallel}) {
    auto queue = std::make_shared<FrameQueue>(1, Overflow::KeepLatest);
    std::vector<long> rss;
    std::thread producer([&] {
      for (int i = 0; i < 1000; ++i) {
        TestFrame f = base;  // a fresh buffer per frame, as a camera gives
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
    // ASan does not reuse freed memory at once: it holds it in its quarantine (256 MB by
    // default, ASAN_OPTIONS quarantine_size_mb), so RSS grows by up to that much with no leak.
    // Keeping every frame would still fail: 1000 frames of 1.2 MB.
#ifdef MEREO_TEST_ASAN
    const long bound_kb = (20 + 300) * 1024;
#else
    const long bound_kb = 20 * 1024;
#endif
    const long early = *std::max_element(rss.begin(), rss.begin() + 4);
    const long late = *std::max_element(rss.begin() + 4, rss.end());
    EXPECT_LT(late - early, bound_kb) << "RSS grew from " << early << " kB to " << late << " kB";
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
      const auto& d = ctx.input<TestFrame>("frame").depth;
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
  std::vector<TestFrame> frames(sequence50().begin(), sequence50().begin() + 5);
  const auto r = g.run_all(FrameSource::recorded(frames), o);
  ASSERT_EQ(r.size(), 5u);
  EXPECT_EQ(r[0].outputs.size(), 1u);
  EXPECT_GT(r[0].outputs.at("valid.n").get<double>(), 1000);
  const auto trace = nlohmann::json::parse(g.trace_json());
  EXPECT_EQ(trace["traceEvents"].size(), 5u * 4u);
  EXPECT_EQ(trace["traceEvents"][0]["ph"], "X");
  EXPECT_THROW(g.to_yaml(), GraphError);  // a custom node cannot be saved
}

TEST(GraphRun, SourceItemsAndSourceValuesOfAnotherType) {
  Graph g = small_graph();
  RunOptions o;
  o.keep = {"work1.value"};
  // Items made by hand equal the frames they wrap; load() runs on any thread in parallel mode.
  const auto& frames = sequence50();
  const auto a = g.run_all(FrameSource::recorded(std::vector<TestFrame>(frames.begin(), frames.begin() + 3)), o);
  const auto b = g.run_all(
      FrameSource::from_function(3, [&](std::size_t i) { return SourceItem{"item" + std::to_string(i), Value::make(frames[i])}; }), o);
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(a[2].frame_id, "0002");
  EXPECT_EQ(b[2].frame_id, "item2");
  EXPECT_EQ(a[2].outputs.at("work1.value").get<double>(), b[2].outputs.at("work1.value").get<double>());
  // A value that is not the source port's type fails its frame at the source node.
  for (Mode mode : {Mode::Deterministic, Mode::Parallel}) {
    o.mode = mode;
    o.on_error = ErrorPolicy::Skip;
    const auto r = g.run_all(FrameSource::recorded({SourceItem{"x", Value::make(1.5)}, SourceItem::of(frames[0])}), o);
    ASSERT_EQ(r.size(), 2u);
    ASSERT_FALSE(r[0].ok());
    EXPECT_EQ(r[0].error->node, "source");
    EXPECT_NE(std::string(r[0].error->what()).find("a value of type Number cannot pass as Frame"), std::string::npos)
        << r[0].error->what();
    EXPECT_TRUE(r[1].ok());
  }
}

TEST(Values, TypesAreRegisteredOnceByNameAndShareACppType) {
  EXPECT_NE(find_type("Number"), nullptr);  // the engine's own types
  EXPECT_NE(find_type("Text"), nullptr);
  EXPECT_EQ(find_type("NoSuchType"), nullptr);
  register_type<Depth>("Depth");  // again: nothing changes
  register_type<Depth>("Heights");  // a second name of the same C++ type
  EXPECT_EQ(type_of<Depth>().name, "Depth");  // the first name
  EXPECT_THROW(register_type<double>("Depth"), std::logic_error);  // a name means one C++ type
  const Value v = Value::make(Depth{{1.0f, 2.0f}});
  EXPECT_EQ(v.describe(), "2 depth values");
  EXPECT_EQ(v.as(*find_type("Heights")).type().name, "Heights");
  EXPECT_THROW(v.as(*find_type("Number")), std::logic_error);
  EXPECT_THROW(v.get<double>(), std::logic_error);
  EXPECT_EQ(Value::make(0.1).describe(), "0.10000000000000001");
  struct Unregistered {};
  EXPECT_THROW(Value::make(Unregistered{}), std::logic_error);
  const auto names = type_names();
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
}

TEST(Registry, KindsAreRegisteredOnce) {
  EXPECT_THROW(register_node(mereo::test_nodes::identity_node()), GraphError);
  mereo::test_nodes::register_test_nodes<TestFrame>();  // idempotent
  std::vector<std::string> kinds;
  for (const auto& s : node_specs()) kinds.push_back(s.kind);
  EXPECT_EQ(kinds, (std::vector<std::string>{"frame_source", "scale_depth", "identity", "checksum", "fail_on_frame"}));
  EXPECT_EQ(node_spec("checksum").option("rounds")->doc, "passes over the image");
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  register_test_kinds();
  return RUN_ALL_TESTS();
}
