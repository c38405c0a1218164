// mereo/graph/graph.hpp: a graph of nodes, its checks, files, drawing and execution.
//
// Build a graph in C++ or Python (add nodes, connect "node.port" to "node.port"), or load it
// from a YAML file in graphs/. verify() checks it before anything runs. run() drives it over
// a frame source in one of two modes that give identical results:
//  - Deterministic: one frame at a time, in order, on the calling thread;
//  - Parallel: a oneTBB flow graph; independent nodes of a frame run concurrently, up to
//    `max_in_flight` frames at once, results delivered in frame order.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mereo/graph/node.hpp"
#include "mereo/graph/value.hpp"

namespace mereo::graph {

/// A mistake in a graph (unknown kind, bad option, dangling port, cycle...). The message
/// names the node and the port, and for a file the file and line.
class GraphError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A node that threw while processing a frame.
class NodeError : public std::runtime_error {
 public:
  NodeError(std::string node, std::size_t frame_index, std::string frame_id, std::string cause);
  std::string node;
  std::size_t frame_index;
  std::string frame_id;
  std::string cause;
};

struct NodeInstance {
  std::string name;
  std::string kind;
  Options options;
  std::map<std::string, OptionValue> given;  ///< options as written (for saving)
  std::string file;                          ///< the graph file that defines it (a base file of
                                             ///< `extends`), empty if built in code
  int line = 0;                              ///< line in that file, 0 if built in code
  std::shared_ptr<const NodeSpec> custom;    ///< graph-local spec (Python nodes), else null
  const NodeSpec& spec() const;
};

struct Edge {
  std::string from_node, from_port, to_node, to_port;
  std::string file;  ///< the graph file that has it, empty if built in code
  int line = 0;
};

/// What happens when a live source produces frames faster than the graph takes them.
enum class Overflow {
  Block,       ///< the producer waits (no frame is lost)
  DropOldest,  ///< the oldest waiting frame is dropped
  KeepLatest,  ///< only the newest frame waits; older ones are dropped
};
Overflow overflow_from_string(const std::string& s);  ///< "block", "drop_oldest", "keep_latest"
const char* to_string(Overflow o);

/// One frame of a run, as the engine sees it: the value that the source nodes put out (a
/// mereo::Frame in the library) and its id, which results and errors carry.
struct SourceItem {
  std::string id;
  Value value;
  /// The item of `frame`: F is a registered port type with a string member `id` (mereo::Frame).
  template <typename F>
  static SourceItem of(F frame) {
    std::string id = frame.id;
    return {std::move(id), Value::make<F>(std::move(frame))};
  }
};

/// A thread-safe, bounded queue of frames between a live producer and a running graph.
class FrameQueue {
 public:
  explicit FrameQueue(std::size_t capacity = 2, Overflow policy = Overflow::Block);
  /// Adds a frame (may block, drop the oldest, or replace, by policy). False if closed.
  bool push(SourceItem frame);
  /// push(SourceItem::of(frame)), for a frame F as SourceItem::of takes it.
  template <typename F>
  bool push(F frame) { return push(SourceItem::of(std::move(frame))); }
  /// Waits for a frame; nullopt once closed and empty.
  std::optional<SourceItem> pop();
  /// No more frames: pop() drains what is queued, then returns nullopt.
  void close();
  std::size_t pushed() const { return pushed_; }
  std::size_t dropped() const { return dropped_; }
  std::size_t capacity() const { return capacity_; }
  Overflow policy() const { return policy_; }

 private:
  std::size_t capacity_;
  Overflow policy_;
  std::mutex mutex_;
  std::condition_variable not_empty_, not_full_;
  std::deque<SourceItem> frames_;
  bool closed_ = false;
  std::atomic<std::size_t> pushed_{0}, dropped_{0};
};

/// Where frames come from: a recorded sequence (indexable) or a live queue. The factories take
/// SourceItems or frames F as SourceItem::of takes them (mereo::Frame).
struct FrameSource {
  std::function<std::size_t()> size;                   ///< recorded: number of frames
  std::function<SourceItem(std::size_t)> load;         ///< recorded: frame i (called on any thread)
  std::shared_ptr<FrameQueue> live;                    ///< live: frames as they come
  static FrameSource recorded(std::vector<SourceItem> frames);
  template <typename F>
  static FrameSource recorded(std::vector<F> frames) {
    std::vector<SourceItem> items;
    items.reserve(frames.size());
    for (auto& f : frames) items.push_back(SourceItem::of(std::move(f)));
    return recorded(std::move(items));
  }
  template <typename F>
  static FrameSource recorded(std::initializer_list<F> frames) { return recorded(std::vector<F>(frames)); }
  /// n frames; `load(i)` returns frame i (a SourceItem or a frame F).
  template <typename Load>
  static FrameSource from_function(std::size_t n, Load load) {
    using F = std::decay_t<std::invoke_result_t<Load&, std::size_t>>;
    FrameSource s;
    s.size = [n] { return n; };
    if constexpr (std::is_same_v<F, SourceItem>)
      s.load = std::move(load);
    else
      s.load = [load = std::move(load)](std::size_t i) { return SourceItem::of<F>(load(i)); };
    return s;
  }
  static FrameSource from_queue(std::shared_ptr<FrameQueue> queue);
};

enum class Mode { Deterministic, Parallel };
enum class ErrorPolicy { Stop, Skip };

struct RunOptions {
  Mode mode = Mode::Deterministic;
  std::size_t max_in_flight = 4;   ///< parallel: frames in the graph at once (K)
  ErrorPolicy on_error = ErrorPolicy::Stop;
  bool trace = false;              ///< record a Chrome trace (Graph::write_trace)
  /// Outputs to keep per frame ("node.port"); empty = the outputs of the sink nodes (those
  /// whose outputs feed nothing).
  std::vector<std::string> keep;
};

/// The outputs of one frame, in frame order.
struct FrameResult {
  std::size_t index = 0;
  std::string frame_id;
  std::map<std::string, Value> outputs;  ///< "node.port" -> value
  std::optional<NodeError> error;        ///< set when a node failed (Skip policy)
  std::map<std::string, double> timings_ms;  ///< node name -> its time on this frame
  bool ok() const { return !error; }
};

/// Timing statistics of one node over a run, milliseconds.
struct NodeTiming {
  std::string node;
  std::size_t count = 0;
  double mean_ms = 0, median_ms = 0, max_ms = 0, total_ms = 0;
};

struct RunSummary {
  std::size_t frames = 0;        ///< frames that entered the graph
  std::size_t completed = 0;     ///< frames whose every node ran
  std::size_t failed = 0;        ///< frames with a node error (Skip policy)
  std::size_t dropped = 0;       ///< live frames dropped by the overflow policy
  double wall_ms = 0;
  std::vector<NodeTiming> timings;
};

class Graph {
 public:
  Graph();
  ~Graph();
  Graph(Graph&&) noexcept;
  Graph& operator=(Graph&&) noexcept;

  /// Adds a node of a registered kind; `name` must be unique (empty: kind + number).
  /// Option values are validated at once (GraphError names the node and option).
  const NodeInstance& add(const std::string& kind, std::string name = {},
                          const std::map<std::string, OptionValue>& options = {}, int line = 0);
  /// Adds a node with a graph-local spec (a Python callable, a test node).
  const NodeInstance& add_custom(NodeSpec spec, std::string name);
  /// Connects "node.port" to "node.port" (checked by verify(), not here, so that a graph can
  /// be built in any order).
  void connect(const std::string& from, const std::string& to, int line = 0);
  void connect(const std::string& from_node, const std::string& from_port, const std::string& to_node,
               const std::string& to_port, int line = 0);
  /// Sets the overflow policy and queue length of the live source's edges.
  void set_overflow(Overflow policy, std::size_t capacity = 2);
  /// Changes options of node `name` (the others keep their values); checked like add()'s.
  /// Throws GraphError naming the node and the option.
  void set_options(const std::string& name, const std::map<std::string, OptionValue>& options);

  /// Checks kinds, ports, port types, required inputs, option values and cycles; throws
  /// GraphError naming the node and port (and the file and line for loaded graphs). It makes
  /// the node bodies (what a node checks when it is made, a model file or a list of classes,
  /// fails here) and keeps them for the next run, so that a run makes each body once.
  void verify() const;

  const std::vector<NodeInstance>& nodes() const { return nodes_; }
  const std::vector<Edge>& edges() const { return edges_; }
  const NodeInstance& node(const std::string& name) const;
  const std::string& file() const { return file_; }
  Overflow overflow() const { return overflow_; }
  std::size_t overflow_capacity() const { return overflow_capacity_; }

  /// YAML graph files (graphs/*.yaml): see graphs/README.md for the format. A file may extend
  /// another (`extends: base.yaml`, relative to the file; for parse(), to `file_name`'s folder):
  /// the base's nodes and edges, then the file's nodes (a name the base has: its options
  /// override the base's) and edges (one into an input the base feeds replaces the base's).
  static Graph load(const std::string& path);
  static Graph parse(const std::string& yaml_text, const std::string& file_name = "<text>");
  /// A self-contained file (no `extends`): every node with the options given to it.
  std::string to_yaml() const;
  void save(const std::string& path) const;
  /// A graphviz drawing (dot language): nodes with their kinds, edges labelled by port.
  std::string to_dot() const;

  /// Runs the graph over `source`; `on_result` receives each frame's result in frame order
  /// (on one thread at a time). With ErrorPolicy::Stop the first NodeError is thrown after
  /// the frames before it were delivered.
  RunSummary run(const FrameSource& source, const RunOptions& options,
                 const std::function<void(FrameResult&&)>& on_result = {});
  /// run() collecting every result in a vector.
  std::vector<FrameResult> run_all(const FrameSource& source, const RunOptions& options,
                                   RunSummary* summary = nullptr);

  /// The timings and trace of the last run.
  const RunSummary& last_summary() const { return last_summary_; }
  /// Chrome trace JSON (chrome://tracing, Perfetto) of the last run with options.trace.
  std::string trace_json() const;
  void write_trace(const std::string& path) const;

 private:
  friend struct GraphRunner;
  const NodeInstance& add_at(const std::string& file, int line, const std::string& kind, std::string name,
                             const std::map<std::string, OptionValue>& options);
  void connect_at(const std::string& file, int line, const std::string& from, const std::string& to);
  /// Adds the nodes, edges and live settings of a graph file (after those of the file it extends).
  void read_yaml(const std::string& text, const std::string& file, std::vector<std::string>& chain);
  std::vector<NodeInstance> nodes_;
  std::vector<Edge> edges_;
  std::string file_;
  Overflow overflow_ = Overflow::Block;
  std::size_t overflow_capacity_ = 2;
  /// Bodies made by verify() for the nodes' current options, by node name; a run takes them
  /// (and a node's state, a tracker's, is per run), set_options() drops the node's.
  mutable std::map<std::string, NodeBody> bodies_;
  RunSummary last_summary_;
  struct TraceEvent {
    std::string node;
    std::size_t frame;
    double start_us, dur_us;
    int thread;
  };
  std::vector<TraceEvent> trace_;
};

}  // namespace mereo::graph
