// Graph execution: the deterministic mode (in order, on the calling thread) and the parallel
// mode (a oneTBB flow graph with up to K frames in flight, results re-ordered). Both run the
// same per-node step, so they give the same values.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <tbb/flow_graph.h>

#include "mereo/graph/graph.hpp"

namespace mereo::graph {

namespace {

using Clock = std::chrono::steady_clock;

int thread_number() {
  static std::atomic<int> next{0};
  thread_local int id = next++;
  return id;
}

}  // namespace

/// A graph compiled for one run: node bodies, port-to-slot maps, successors.
struct GraphRunner {
  struct CNode {
    const NodeInstance* inst = nullptr;
    const NodeSpec* spec = nullptr;
    NodeBody body;
    std::vector<int> input_slot;   // per spec input: slot index, -1 if unconnected
    std::vector<int> output_slot;  // per spec output
    std::vector<int> successors;   // distinct successor nodes
    int predecessors = 0;          // distinct predecessor nodes
    std::mutex timing_mutex;
    std::vector<double> times_ms;
  };

  struct FrameState {
    std::size_t index = 0;   // sequence number in the run
    std::string id;
    std::vector<Value> slots;
    std::unique_ptr<std::atomic<int>[]> pending;
    std::atomic<int> sinks_pending{0};
    std::atomic<bool> failed{false};
    std::mutex error_mutex;
    std::optional<NodeError> error;
    std::vector<double> node_ms;  // per node: its time on this frame (each written once)
  };
  using Msg = std::shared_ptr<FrameState>;

  class Context final : public NodeContext {
   public:
    Context(const CNode& n, FrameState& s) : n_(n), s_(s) {}
    bool has_input(const std::string& port) const override {
      for (std::size_t i = 0; i < n_.spec->inputs.size(); ++i)
        if (n_.spec->inputs[i].name == port) return n_.input_slot[i] >= 0 && !s_.slots[n_.input_slot[i]].empty();
      return false;
    }
    const Value& input_value(const std::string& port) const override {
      for (std::size_t i = 0; i < n_.spec->inputs.size(); ++i)
        if (n_.spec->inputs[i].name == port) {
          if (n_.input_slot[i] < 0) throw std::logic_error("input port '" + port + "' is not connected");
          const Value& v = s_.slots[n_.input_slot[i]];
          if (v.empty()) throw std::logic_error("input port '" + port + "' received no value");
          return v;
        }
      throw std::logic_error("node has no input port '" + port + "'");
    }
    void set_output(const std::string& port, Value v) override {
      for (std::size_t i = 0; i < n_.spec->outputs.size(); ++i)
        if (n_.spec->outputs[i].name == port) {
          const TypeInfo* t = find_type(n_.spec->outputs[i].type);
          if (!t) throw std::logic_error("output port '" + port + "' has an unregistered type");
          s_.slots[n_.output_slot[i]] = v.as(*t);
          return;
        }
      throw std::logic_error("node has no output port '" + port + "'");
    }
    std::size_t frame_index() const override { return s_.index; }
    const std::string& frame_id() const override { return s_.id; }

   private:
    const CNode& n_;
    FrameState& s_;
  };

  Graph& graph;
  const RunOptions& options;
  std::vector<std::unique_ptr<CNode>> nodes;  // in topological order
  std::vector<std::string> slot_names;
  std::vector<int> keep_slots;
  std::vector<int> sinks;
  std::vector<std::pair<int, Value>> constants;  // slot -> the output of a constant node
  Clock::time_point t0 = Clock::now();
  std::mutex trace_mutex;

  GraphRunner(Graph& g, const RunOptions& o) : graph(g), options(o) {
    g.verify();
    // Topological order (stable: the order of the file among ready nodes).
    const auto& inst = g.nodes_;
    std::map<std::string, int> index;
    for (std::size_t i = 0; i < inst.size(); ++i) index[inst[i].name] = int(i);
    std::vector<std::set<int>> succ(inst.size());
    std::vector<int> indeg(inst.size(), 0);
    for (const auto& e : g.edges_)
      if (succ[index[e.from_node]].insert(index[e.to_node]).second) ++indeg[index[e.to_node]];
    std::vector<int> order, deg = indeg;
    std::vector<bool> done(inst.size(), false);
    while (order.size() < inst.size())
      for (std::size_t i = 0; i < inst.size(); ++i)
        if (!done[i] && deg[i] == 0) {
          done[i] = true;
          order.push_back(int(i));
          for (int s : succ[i]) --deg[s];
          break;
        }
    std::vector<int> position(inst.size());
    for (std::size_t k = 0; k < order.size(); ++k) position[order[k]] = int(k);
    // Output slots.
    std::map<std::pair<std::string, std::string>, int> slot_of;
    for (int i : order)
      for (const auto& p : inst[i].spec().outputs) {
        slot_of[{inst[i].name, p.name}] = int(slot_names.size());
        slot_names.push_back(inst[i].name + "." + p.name);
      }
    for (int i : order) {
      auto c = std::make_unique<CNode>();
      c->inst = &inst[i];
      c->spec = &inst[i].spec();
      // the body verify() made for this run (each body is made once per run)
      auto body = g.bodies_.find(inst[i].name);
      if (body == g.bodies_.end())
        throw GraphError("node '" + inst[i].name + "' (" + inst[i].kind + "): its kind has no body");
      c->body = std::move(body->second);
      g.bodies_.erase(body);
      for (const auto& p : c->spec->inputs) {
        int slot = -1;
        for (const auto& e : g.edges_)
          if (e.to_node == inst[i].name && e.to_port == p.name) slot = slot_of.at({e.from_node, e.from_port});
        c->input_slot.push_back(slot);
      }
      for (const auto& p : c->spec->outputs) c->output_slot.push_back(slot_of.at({inst[i].name, p.name}));
      for (int s : succ[i]) c->successors.push_back(position[s]);
      std::sort(c->successors.begin(), c->successors.end());
      c->predecessors = indeg[i];
      nodes.push_back(std::move(c));
    }
    for (std::size_t k = 0; k < nodes.size(); ++k)
      if (nodes[k]->successors.empty()) sinks.push_back(int(k));
    // Constant nodes (the knowledge base) run once, now; their outputs go to every frame.
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      if (!nodes[k]->spec->constant) continue;
      FrameState once;
      once.slots.resize(slot_names.size());
      const auto start = Clock::now();
      try {
        Context ctx(*nodes[k], once);
        nodes[k]->body(ctx);
      } catch (const std::exception& e) {
        throw GraphError("node '" + nodes[k]->inst->name + "' (" + nodes[k]->inst->kind + "): " + e.what());
      }
      nodes[k]->times_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
      for (std::size_t i = 0; i < nodes[k]->output_slot.size(); ++i) {
        const int slot = nodes[k]->output_slot[i];
        if (once.slots[slot].empty())
          throw GraphError("node '" + nodes[k]->inst->name + "' (" + nodes[k]->inst->kind +
                           "): produced no value on output port '" + nodes[k]->spec->outputs[i].name + "'");
        constants.emplace_back(slot, once.slots[slot]);
      }
    }
    if (o.keep.empty()) {
      for (int k : sinks)
        for (int s : nodes[k]->output_slot) keep_slots.push_back(s);
    } else {
      for (const auto& name : o.keep) {
        auto it = std::find(slot_names.begin(), slot_names.end(), name);
        if (it == slot_names.end()) throw GraphError("run: no output port '" + name + "' to keep (write node.port)");
        keep_slots.push_back(int(it - slot_names.begin()));
      }
    }
  }

  Msg new_state(std::size_t index) {
    auto s = std::make_shared<FrameState>();
    s->index = index;
    s->slots.resize(slot_names.size());
    for (const auto& [slot, v] : constants) s->slots[slot] = v;
    s->node_ms.assign(nodes.size(), -1.0);
    s->pending.reset(new std::atomic<int>[nodes.size()]);
    for (std::size_t k = 0; k < nodes.size(); ++k) s->pending[k] = std::max(1, nodes[k]->predecessors);
    s->sinks_pending = int(sinks.size());
    return s;
  }

  void fail(FrameState& s, const std::string& node, const std::string& cause) {
    std::lock_guard<std::mutex> lock(s.error_mutex);
    if (!s.error) s.error.emplace(node, s.index, s.id, cause);
    s.failed = true;
  }

  /// Puts the frame's value on the source nodes' outputs, as their ports' type (a value of
  /// another C++ type fails the frame at its source node).
  void set_frame(FrameState& s, SourceItem frame) {
    s.id = std::move(frame.id);
    for (auto& n : nodes) {
      if (!n->spec->is_source) continue;
      for (std::size_t i = 0; i < n->output_slot.size(); ++i) {
        const TypeInfo* t = find_type(n->spec->outputs[i].type);
        try {
          if (!t) throw std::logic_error("output port '" + n->spec->outputs[i].name + "' has an unregistered type");
          s.slots[n->output_slot[i]] = frame.value.as(*t);
        } catch (const std::exception& e) {
          fail(s, n->inst->name, e.what());
        }
      }
    }
  }

  /// Runs node k on a frame (the step both modes share).
  void step(int k, FrameState& s) {
    CNode& n = *nodes[k];
    if (s.failed || n.spec->is_source || n.spec->constant) return;
    const auto start = Clock::now();
    try {
      Context ctx(n, s);
      n.body(ctx);
      for (std::size_t i = 0; i < n.output_slot.size(); ++i)
        if (s.slots[n.output_slot[i]].empty())
          throw std::logic_error("produced no value on output port '" + n.spec->outputs[i].name + "'");
    } catch (const std::exception& e) {
      fail(s, n.inst->name, e.what());
    } catch (...) {
      fail(s, n.inst->name, "unknown exception");
    }
    const auto end = Clock::now();
    const double ms = std::chrono::duration<double, std::milli>(end - start).count();
    s.node_ms[k] = ms;
    {
      std::lock_guard<std::mutex> lock(n.timing_mutex);
      n.times_ms.push_back(ms);
    }
    if (options.trace) {
      std::lock_guard<std::mutex> lock(trace_mutex);
      graph.trace_.push_back({n.inst->name, s.index,
                              std::chrono::duration<double, std::micro>(start - t0).count(), ms * 1000.0,
                              thread_number()});
    }
  }

  FrameResult result_of(FrameState& s) {
    FrameResult r;
    r.index = s.index;
    r.frame_id = s.id;
    for (int slot : keep_slots)
      if (!s.slots[slot].empty()) r.outputs.emplace(slot_names[slot], s.slots[slot]);
    r.error = s.error;
    for (std::size_t k = 0; k < nodes.size(); ++k)
      if (s.node_ms[k] >= 0 && !nodes[k]->spec->is_source) r.timings_ms.emplace(nodes[k]->inst->name, s.node_ms[k]);
    return r;
  }

  RunSummary summary(std::size_t frames, std::size_t completed, std::size_t failed, std::size_t dropped) {
    RunSummary sum;
    sum.frames = frames;
    sum.completed = completed;
    sum.failed = failed;
    sum.dropped = dropped;
    sum.wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    for (auto& n : nodes) {
      if (n->spec->is_source) continue;
      NodeTiming t;
      t.node = n->inst->name;
      auto v = n->times_ms;
      t.count = v.size();
      if (!v.empty()) {
        for (double x : v) t.total_ms += x;
        t.mean_ms = t.total_ms / v.size();
        t.max_ms = *std::max_element(v.begin(), v.end());
        std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
        t.median_ms = v[v.size() / 2];
      }
      sum.timings.push_back(t);
    }
    return sum;
  }

  // ---- deterministic ----------------------------------------------------------------------
  RunSummary run_deterministic(const FrameSource& src, const std::function<void(FrameResult&&)>& sink) {
    std::size_t frames = 0, completed = 0, failed = 0;
    auto process = [&](SourceItem frame) {
      auto s = new_state(frames++);
      set_frame(*s, std::move(frame));
      for (std::size_t k = 0; k < nodes.size(); ++k) step(int(k), *s);
      if (s->error) {
        ++failed;
        if (options.on_error == ErrorPolicy::Stop) {
          graph.last_summary_ = summary(frames, completed, failed, src.live ? src.live->dropped() : 0);
          throw *s->error;
        }
      } else {
        ++completed;
      }
      if (sink) sink(result_of(*s));
    };
    if (src.live) {
      while (auto f = src.live->pop()) process(std::move(*f));
    } else {
      const std::size_t n = src.size();
      for (std::size_t i = 0; i < n; ++i) {
        SourceItem f;
        try {
          f = src.load(i);
        } catch (const std::exception& e) {
          throw NodeError("frame_source", i, "", e.what());
        }
        process(std::move(f));
      }
    }
    return summary(frames, completed, failed, src.live ? src.live->dropped() : 0);
  }

  // ---- parallel (oneTBB flow graph) -----------------------------------------------------------
  RunSummary run_parallel(const FrameSource& src, const std::function<void(FrameResult&&)>& sink) {
    namespace flow = tbb::flow;
    flow::graph g;
    std::atomic<bool> stop{false};
    std::size_t admitted = 0, completed = 0, failed = 0;
    std::optional<NodeError> first_error;
    std::exception_ptr sink_error;
    const std::size_t total = src.live ? 0 : src.size();

    // Admission: sequence numbers in order; recorded frames are loaded later, in parallel.
    flow::input_node<Msg> input(g, [&](tbb::flow_control& fc) -> Msg {
      if (stop) {
        fc.stop();
        return nullptr;
      }
      if (src.live) {
        auto f = src.live->pop();
        if (!f) {
          fc.stop();
          return nullptr;
        }
        auto s = new_state(admitted++);
        set_frame(*s, std::move(*f));
        return s;
      }
      if (admitted >= total) {
        fc.stop();
        return nullptr;
      }
      return new_state(admitted++);
    });
    flow::limiter_node<Msg> limiter(g, std::max<std::size_t>(1, options.max_in_flight));
    flow::function_node<Msg, Msg> load(g, flow::unlimited, [&](Msg s) {
      if (!src.live) {
        try {
          set_frame(*s, src.load(s->index));
        } catch (const std::exception& e) {
          fail(*s, "frame_source", e.what());
        }
      }
      return s;
    });
    using Stage = flow::multifunction_node<Msg, std::tuple<Msg>>;
    std::vector<std::unique_ptr<Stage>> stages;
    // An ordered node gets its frames through a gate (the join of its predecessors: one message
    // per frame) and a sequencer (frame order), then runs serially.
    std::vector<std::unique_ptr<Stage>> gates(nodes.size());
    std::vector<std::unique_ptr<flow::sequencer_node<Msg>>> sequencers(nodes.size());
    std::vector<flow::receiver<Msg>*> entry(nodes.size());
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const bool ordered = nodes[k]->spec->ordered;
      const std::size_t concurrency = nodes[k]->spec->serial || ordered ? flow::serial : flow::unlimited;
      stages.push_back(std::make_unique<Stage>(g, concurrency, [this, k, ordered](Msg s, Stage::output_ports_type& out) {
        if (!ordered && --s->pending[k] != 0) return;  // waits for its other predecessors
        step(int(k), *s);
        std::get<0>(out).try_put(s);
      }));
      entry[k] = stages[k].get();
      if (!ordered) continue;
      gates[k] = std::make_unique<Stage>(g, flow::unlimited, [k](Msg s, Stage::output_ports_type& out) {
        if (--s->pending[k] == 0) std::get<0>(out).try_put(s);
      });
      sequencers[k] = std::make_unique<flow::sequencer_node<Msg>>(g, [](const Msg& s) { return s->index; });
      flow::make_edge(flow::output_port<0>(*gates[k]), *sequencers[k]);
      flow::make_edge(*sequencers[k], *stages[k]);
      entry[k] = gates[k].get();
    }
    Stage done(g, flow::unlimited, [](Msg s, Stage::output_ports_type& out) {
      if (--s->sinks_pending == 0) std::get<0>(out).try_put(s);
    });
    flow::sequencer_node<Msg> order(g, [](const Msg& s) { return s->index; });
    flow::function_node<Msg, flow::continue_msg> deliver(g, flow::serial, [&](Msg s) {
      if (!stop) {
        if (s->error) {
          ++failed;
          if (options.on_error == ErrorPolicy::Stop) {
            first_error = s->error;
            stop = true;
          }
        } else {
          ++completed;
        }
        if (!stop || options.on_error == ErrorPolicy::Skip) {
          try {
            if (sink) sink(result_of(*s));
          } catch (...) {
            sink_error = std::current_exception();
            stop = true;
          }
        }
      }
      return flow::continue_msg();
    });

    flow::make_edge(input, limiter);
    flow::make_edge(limiter, load);
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      if (nodes[k]->predecessors == 0) flow::make_edge(load, *entry[k]);
      for (int s : nodes[k]->successors) flow::make_edge(flow::output_port<0>(*stages[k]), *entry[s]);
      if (nodes[k]->successors.empty()) flow::make_edge(flow::output_port<0>(*stages[k]), done);
    }
    flow::make_edge(flow::output_port<0>(done), order);
    flow::make_edge(order, deliver);
    flow::make_edge(deliver, limiter.decrementer());
    input.activate();
    g.wait_for_all();

    graph.last_summary_ = summary(admitted, completed, failed, src.live ? src.live->dropped() : 0);
    if (sink_error) std::rethrow_exception(sink_error);
    if (first_error) throw *first_error;
    return graph.last_summary_;
  }
};

RunSummary Graph::run(const FrameSource& source, const RunOptions& options,
                      const std::function<void(FrameResult&&)>& on_result) {
  if (!source.live && (!source.size || !source.load)) throw GraphError("run: the frame source is empty");
  trace_.clear();
  GraphRunner runner(*this, options);
  last_summary_ = options.mode == Mode::Parallel ? runner.run_parallel(source, on_result)
                                                 : runner.run_deterministic(source, on_result);
  return last_summary_;
}

std::vector<FrameResult> Graph::run_all(const FrameSource& source, const RunOptions& options, RunSummary* summary) {
  std::vector<FrameResult> out;
  const auto s = run(source, options, [&](FrameResult&& r) { out.push_back(std::move(r)); });
  if (summary) *summary = s;
  return out;
}

std::string Graph::trace_json() const {
  nlohmann::json events = nlohmann::json::array();
  for (const auto& e : trace_)
    events.push_back({{"name", e.node}, {"cat", "node"}, {"ph", "X"}, {"ts", e.start_us}, {"dur", e.dur_us},
                      {"pid", 1}, {"tid", e.thread}, {"args", {{"frame", e.frame}}}});
  return nlohmann::json{{"traceEvents", events}, {"displayTimeUnit", "ms"}}.dump();
}

void Graph::write_trace(const std::string& path) const {
  std::ofstream out(path);
  if (!out) throw GraphError(path + ": cannot write the trace");
  out << trace_json();
}

}  // namespace mereo::graph
