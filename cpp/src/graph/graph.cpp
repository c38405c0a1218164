// Graph construction, verification, YAML files and the graphviz drawing.
#include "mereo/graph/graph.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace mereo::graph {

// ---- small types ------------------------------------------------------------------------

NodeError::NodeError(std::string node_, std::size_t frame_index_, std::string frame_id_, std::string cause_)
    : std::runtime_error("node '" + node_ + "' failed on frame " + std::to_string(frame_index_) +
                         (frame_id_.empty() ? std::string() : " ('" + frame_id_ + "')") + ": " + cause_),
      node(std::move(node_)),
      frame_index(frame_index_),
      frame_id(std::move(frame_id_)),
      cause(std::move(cause_)) {}

const NodeSpec& NodeInstance::spec() const { return custom ? *custom : node_spec(kind); }

Overflow overflow_from_string(const std::string& s) {
  if (s == "block") return Overflow::Block;
  if (s == "drop_oldest") return Overflow::DropOldest;
  if (s == "keep_latest") return Overflow::KeepLatest;
  throw GraphError("overflow policy '" + s + "' is not one of: block, drop_oldest, keep_latest");
}

const char* to_string(Overflow o) {
  switch (o) {
    case Overflow::Block: return "block";
    case Overflow::DropOldest: return "drop_oldest";
    case Overflow::KeepLatest: return "keep_latest";
  }
  return "?";
}

FrameQueue::FrameQueue(std::size_t capacity, Overflow policy)
    : capacity_(policy == Overflow::KeepLatest ? 1 : std::max<std::size_t>(capacity, 1)), policy_(policy) {}

bool FrameQueue::push(SourceItem frame) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (closed_) return false;
  if (frames_.size() >= capacity_) {
    if (policy_ == Overflow::Block) {
      not_full_.wait(lock, [&] { return frames_.size() < capacity_ || closed_; });
      if (closed_) return false;
    } else {
      frames_.pop_front();  // drop_oldest, and keep_latest with its one place
      ++dropped_;
    }
  }
  frames_.push_back(std::move(frame));
  ++pushed_;
  not_empty_.notify_one();
  return true;
}

std::optional<SourceItem> FrameQueue::pop() {
  std::unique_lock<std::mutex> lock(mutex_);
  not_empty_.wait(lock, [&] { return !frames_.empty() || closed_; });
  if (frames_.empty()) return std::nullopt;
  SourceItem f = std::move(frames_.front());
  frames_.pop_front();
  not_full_.notify_one();
  return f;
}

void FrameQueue::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  not_empty_.notify_all();
  not_full_.notify_all();
}

FrameSource FrameSource::recorded(std::vector<SourceItem> frames) {
  auto shared = std::make_shared<const std::vector<SourceItem>>(std::move(frames));
  return from_function(shared->size(), [shared](std::size_t i) { return (*shared)[i]; });
}

FrameSource FrameSource::from_queue(std::shared_ptr<FrameQueue> queue) {
  FrameSource s;
  s.live = std::move(queue);
  return s;
}

// ---- building -----------------------------------------------------------------------------

Graph::Graph() = default;
Graph::~Graph() = default;
Graph::Graph(Graph&&) noexcept = default;
Graph& Graph::operator=(Graph&&) noexcept = default;

namespace {

std::string at_line(const std::string& file, int line) {
  if (line <= 0) return {};
  return file + ":" + std::to_string(line) + ": ";
}

bool valid_name(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

std::string port_list(const std::vector<PortSpec>& ports) {
  std::string out;
  for (const auto& p : ports) out += (out.empty() ? "" : ", ") + p.name + " (" + p.type + ")";
  return out.empty() ? "none" : out;
}

}  // namespace

const NodeInstance& Graph::add(const std::string& kind, std::string name,
                               const std::map<std::string, OptionValue>& options, int line) {
  return add_at(file_, line, kind, std::move(name), options);
}

const NodeInstance& Graph::add_at(const std::string& file, int line, const std::string& kind, std::string name,
                                  const std::map<std::string, OptionValue>& options) {
  const std::string where = at_line(file, line);
  const NodeSpec* spec = nullptr;
  try {
    spec = &node_spec(kind);
  } catch (const GraphError& e) {
    throw GraphError(where + (name.empty() ? std::string() : "node '" + name + "': ") + e.what());
  }
  if (name.empty()) {
    for (int i = 1;; ++i) {
      name = kind + std::to_string(i);
      if (std::none_of(nodes_.begin(), nodes_.end(), [&](const auto& n) { return n.name == name; })) break;
    }
  }
  if (!valid_name(name)) throw GraphError(where + "node name '" + name + "' must be letters, digits, _ or -");
  for (const auto& n : nodes_)
    if (n.name == name) throw GraphError(where + "node '" + name + "' is defined twice");
  NodeInstance n;
  n.name = name;
  n.kind = kind;
  n.file = file;
  n.line = line;
  n.given = options;
  try {
    n.options = spec->validate(name, options);
  } catch (const GraphError& e) {
    throw GraphError(where + e.what());
  }
  nodes_.push_back(std::move(n));
  return nodes_.back();
}

void Graph::set_options(const std::string& name, const std::map<std::string, OptionValue>& options) {
  for (auto& n : nodes_) {
    if (n.name != name) continue;
    auto given = n.given;
    for (const auto& [k, v] : options) given[k] = v;
    n.options = n.spec().validate(name, given);
    n.given = std::move(given);
    bodies_.erase(name);  // made for the old options
    return;
  }
  throw GraphError("no node named '" + name + "'");
}

const NodeInstance& Graph::add_custom(NodeSpec spec, std::string name) {
  if (!valid_name(name)) throw GraphError("node name '" + name + "' must be letters, digits, _ or -");
  for (const auto& n : nodes_)
    if (n.name == name) throw GraphError("node '" + name + "' is defined twice");
  NodeInstance n;
  n.name = name;
  n.kind = spec.kind;
  n.options = spec.validate(name, {});
  n.custom = std::make_shared<const NodeSpec>(std::move(spec));
  nodes_.push_back(std::move(n));
  return nodes_.back();
}

void Graph::connect(const std::string& from, const std::string& to, int line) { connect_at(file_, line, from, to); }

void Graph::connect_at(const std::string& file, int line, const std::string& from, const std::string& to) {
  auto split = [&](const std::string& s) {
    const auto dot = s.find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == s.size())
      throw GraphError(at_line(file, line) + "'" + s + "' is not of the form node.port");
    return std::make_pair(s.substr(0, dot), s.substr(dot + 1));
  };
  const auto [fn, fp] = split(from);
  const auto [tn, tp] = split(to);
  edges_.push_back({fn, fp, tn, tp, file, line});
}

void Graph::connect(const std::string& from_node, const std::string& from_port, const std::string& to_node,
                    const std::string& to_port, int line) {
  edges_.push_back({from_node, from_port, to_node, to_port, file_, line});
}

void Graph::set_overflow(Overflow policy, std::size_t capacity) {
  overflow_ = policy;
  overflow_capacity_ = std::max<std::size_t>(capacity, 1);
}

const NodeInstance& Graph::node(const std::string& name) const {
  for (const auto& n : nodes_)
    if (n.name == name) return n;
  throw GraphError("no node named '" + name + "'");
}

// ---- verification -------------------------------------------------------------------------

void Graph::verify() const {
  auto find = [&](const std::string& name) -> const NodeInstance* {
    for (const auto& n : nodes_)
      if (n.name == name) return &n;
    return nullptr;
  };
  std::map<std::pair<std::string, std::string>, const Edge*> fed;
  for (const auto& e : edges_) {
    const std::string where = at_line(e.file, e.line) + "edge " + e.from_node + "." + e.from_port + " -> " +
                              e.to_node + "." + e.to_port + ": ";
    const NodeInstance* a = find(e.from_node);
    const NodeInstance* b = find(e.to_node);
    if (!a) throw GraphError(where + "no node named '" + e.from_node + "'");
    if (!b) throw GraphError(where + "no node named '" + e.to_node + "'");
    const PortSpec* out = a->spec().output(e.from_port);
    const PortSpec* in = b->spec().input(e.to_port);
    if (!out)
      throw GraphError(where + "node '" + a->name + "' (" + a->kind + ") has no output port '" + e.from_port +
                       "' (outputs: " + port_list(a->spec().outputs) + ")");
    if (!in)
      throw GraphError(where + "node '" + b->name + "' (" + b->kind + ") has no input port '" + e.to_port +
                       "' (inputs: " + port_list(b->spec().inputs) + ")");
    if (out->type != in->type)
      throw GraphError(where + "port types differ: " + e.from_node + "." + e.from_port + " is " + out->type +
                       ", " + e.to_node + "." + e.to_port + " takes " + in->type);
    auto key = std::make_pair(e.to_node, e.to_port);
    if (fed.count(key))
      throw GraphError(where + "input port '" + e.to_port + "' of node '" + e.to_node +
                       "' is connected twice (also from " + fed[key]->from_node + "." + fed[key]->from_port + ")");
    fed[key] = &e;
  }
  for (const auto& n : nodes_) {
    const std::string where = at_line(n.file, n.line) + "node '" + n.name + "' (" + n.kind + "): ";
    if (n.spec().constant && !n.spec().inputs.empty())
      throw GraphError(where + "a constant node kind cannot have inputs");
    for (const auto& p : n.spec().inputs)
      if (p.required && !fed.count({n.name, p.name}))
        throw GraphError(where + "required input port '" + p.name + "' (" + p.type + ") is not connected");
    // Option values were checked by add(); check again for options changed since.
    try {
      n.spec().validate(n.name, n.options.values());
    } catch (const GraphError& e) {
      throw GraphError(at_line(n.file, n.line) + e.what());
    }
  }
  // Cycles: Kahn's algorithm; whatever is left lies on or behind a cycle.
  std::map<std::string, int> indegree;
  std::map<std::string, std::set<std::string>> succ;
  for (const auto& n : nodes_) indegree[n.name] = 0;
  for (const auto& e : edges_)
    if (succ[e.from_node].insert(e.to_node).second) ++indegree[e.to_node];
  std::vector<std::string> ready;
  for (const auto& [name, d] : indegree)
    if (d == 0) ready.push_back(name);
  std::size_t seen = 0;
  while (!ready.empty()) {
    const std::string n = ready.back();
    ready.pop_back();
    ++seen;
    for (const auto& s : succ[n])
      if (--indegree[s] == 0) ready.push_back(s);
  }
  if (seen != nodes_.size()) {
    std::string cycle;
    for (const auto& [name, d] : indegree)
      if (d > 0) cycle += (cycle.empty() ? "" : ", ") + name;
    const NodeInstance* first = nullptr;
    for (const auto& [name, d] : indegree)
      if (d > 0 && !first) first = find(name);
    throw GraphError((first ? at_line(first->file, first->line) : std::string()) +
                     "the graph has a cycle through nodes: " + cycle);
  }
  // What a node checks when it is made (a model file, concept names...) fails here, not on the
  // first frame; the body is kept for the next run (bodies_), which then makes no other.
  for (const auto& n : nodes_) {
    if (!n.spec().make || bodies_.count(n.name)) continue;
    try {
      bodies_[n.name] = n.spec().make(n.options);
    } catch (const std::exception& e) {
      throw GraphError(at_line(n.file, n.line) + "node '" + n.name + "' (" + n.kind + "): " + e.what());
    }
  }
}

// ---- YAML files ---------------------------------------------------------------------------

namespace {

int line_of(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

OptionValue option_from_yaml(const YAML::Node& v, const std::string& file, const std::string& where) {
  if (!v.IsScalar()) throw GraphError(file + ":" + std::to_string(line_of(v)) + ": " + where + " must be a single value");
  const std::string text = v.Scalar();
  if (v.Tag() == "!") return text;  // quoted: always text
  if (text == "true" || text == "True") return true;
  if (text == "false" || text == "False") return false;
  try {
    std::size_t used = 0;
    const long long i = std::stoll(text, &used);
    if (used == text.size()) return i;
  } catch (const std::exception&) {
  }
  try {
    std::size_t used = 0;
    const double d = std::stod(text, &used);
    if (used == text.size()) return d;
  } catch (const std::exception&) {
  }
  return text;
}

std::string yaml_value(const OptionValue& v) {
  std::ostringstream s;
  std::visit([&](const auto& x) {
    using T = std::decay_t<decltype(x)>;
    if constexpr (std::is_same_v<T, bool>) s << (x ? "true" : "false");
    else if constexpr (std::is_same_v<T, std::string>) s << '"' << x << '"';
    else if constexpr (std::is_same_v<T, double>) {
      s.precision(17);
      s << x;
      if (s.str().find_first_of(".eEn") == std::string::npos) s << ".0";
    } else s << x;
  }, v);
  return s.str();
}

}  // namespace

namespace {

std::string read_file(const std::string& path, bool* ok) {
  std::ifstream in(path);
  *ok = bool(in);
  std::stringstream s;
  if (in) s << in.rdbuf();
  return s.str();
}

// The same file under every spelling of its path (a cycle of `extends`).
std::string file_key(const std::string& path) {
  std::error_code ec;
  const auto p = std::filesystem::weakly_canonical(path, ec);
  return ec ? path : p.string();
}

}  // namespace

Graph Graph::parse(const std::string& text, const std::string& file) {
  Graph g;
  g.file_ = file;
  std::vector<std::string> chain{file_key(file)};
  try {
    g.read_yaml(text, file, chain);
  } catch (const YAML::Exception& e) {  // a shape the checks in read_yaml did not foresee
    throw GraphError(file + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  g.verify();
  return g;
}

void Graph::read_yaml(const std::string& text, const std::string& file, std::vector<std::string>& chain) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw GraphError(file + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
  auto fail = [&](const YAML::Node& n, const std::string& msg) {
    throw GraphError(file + ":" + std::to_string(line_of(n)) + ": " + msg);
  };
  if (!root.IsMap()) throw GraphError(file + ": a graph file is a mapping with 'nodes' and 'edges'");
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (key != "name" && key != "doc" && key != "extends" && key != "nodes" && key != "edges" && key != "live")
      fail(kv.first, "unknown field '" + key + "' (fields: name, doc, extends, nodes, edges, live)");
  }
  // The base graph first: its nodes and edges, with their own files and lines.
  const YAML::Node base = root["extends"];
  if (base) {
    if (!base.IsScalar() || base.Scalar().empty()) fail(base, "'extends' names one graph file");
    std::filesystem::path path(base.Scalar());
    if (path.is_relative()) path = std::filesystem::path(file).parent_path() / path;
    const std::string key = file_key(path.string());
    if (std::find(chain.begin(), chain.end(), key) != chain.end()) {
      std::string cycle;
      for (const auto& c : chain) cycle += c + " -> ";
      fail(base, "'extends' makes a cycle: " + cycle + key);
    }
    bool ok = false;
    const std::string base_text = read_file(path.string(), &ok);
    if (!ok) fail(base, "cannot open the graph file '" + path.string() + "' that it extends");
    chain.push_back(key);
    try {
      read_yaml(base_text, path.string(), chain);
    } catch (const GraphError& e) {
      throw GraphError(std::string(e.what()) + " (in the graph extended by " + file + ":" +
                       std::to_string(line_of(base)) + ")");
    }
    chain.pop_back();
  }
  const std::size_t inherited_nodes = nodes_.size(), inherited_edges = edges_.size();
  const YAML::Node nodes = root["nodes"];
  if (!nodes && !base) throw GraphError(file + ": 'nodes' must be a list of nodes");
  if (nodes && !nodes.IsSequence()) fail(nodes, "'nodes' must be a list of nodes");
  std::set<std::string> overridden;
  for (const auto& n : nodes ? nodes : YAML::Node(YAML::NodeType::Sequence)) {
    if (!n.IsMap()) fail(n, "a node is a mapping with 'name' and 'kind'");
    for (const auto& kv : n) {
      const std::string key = kv.first.Scalar();
      if (key != "name" && key != "kind" && key != "options")
        fail(kv.first, "unknown field '" + key + "' in a node (fields: name, kind, options)");
    }
    if (!n["name"]) fail(n, "node without 'name'");
    const std::string name = n["name"].Scalar();
    std::map<std::string, OptionValue> options;
    if (const YAML::Node o = n["options"]) {
      if (!o.IsMap()) fail(o, "node '" + name + "': 'options' must be a mapping");
      for (const auto& kv : o)
        options[kv.first.Scalar()] =
            option_from_yaml(kv.second, file, "option '" + kv.first.Scalar() + "' of node '" + name + "'");
    }
    const auto inherited = std::find_if(nodes_.begin(), nodes_.begin() + std::ptrdiff_t(inherited_nodes),
                                        [&](const NodeInstance& x) { return x.name == name; });
    if (inherited == nodes_.begin() + std::ptrdiff_t(inherited_nodes)) {
      if (!n["kind"]) fail(n, "node without 'kind'");
      add_at(file, line_of(n), n["kind"].Scalar(), name, options);
      continue;
    }
    // A node of the base graph: its options are overridden, its kind stays.
    if (!overridden.insert(name).second) fail(n, "node '" + name + "' is defined twice");
    if (n["kind"] && n["kind"].Scalar() != inherited->kind)
      fail(n["kind"], "node '" + name + "' is a " + inherited->kind + " in " + at_line(inherited->file, inherited->line) +
                          "a node of the base graph keeps its kind (give the new node another name)");
    try {
      set_options(name, options);
    } catch (const GraphError& e) {
      fail(n, e.what());
    }
  }
  if (const YAML::Node edges = root["edges"]) {
    if (!edges.IsSequence()) fail(edges, "'edges' must be a list of 'node.port -> node.port'");
    std::set<std::size_t> replaced;
    for (const auto& e : edges) {
      if (!e.IsScalar()) fail(e, "an edge is written 'node.port -> node.port'");
      const std::string s = e.Scalar();
      const auto arrow = s.find("->");
      if (arrow == std::string::npos) fail(e, "edge '" + s + "' has no '->' (write 'node.port -> node.port')");
      auto trim = [](std::string x) {
        x.erase(0, x.find_first_not_of(" \t"));
        x.erase(x.find_last_not_of(" \t") + 1);
        return x;
      };
      connect_at(file, line_of(e), trim(s.substr(0, arrow)), trim(s.substr(arrow + 2)));
      // An edge into an input that the base graph feeds replaces the base's edge, in its place.
      const Edge& added = edges_.back();
      for (std::size_t i = 0; i < inherited_edges; ++i)
        if (edges_[i].to_node == added.to_node && edges_[i].to_port == added.to_port && replaced.insert(i).second) {
          edges_[i] = added;
          edges_.pop_back();
          break;
        }
    }
  }
  if (const YAML::Node live = root["live"]) {
    if (!live.IsMap()) fail(live, "'live' must be a mapping with 'overflow' and 'capacity'");
    Overflow policy = Overflow::Block;
    std::size_t capacity = 2;
    for (const auto& kv : live) {
      const std::string key = kv.first.Scalar();
      if (key == "overflow") {
        try {
          policy = overflow_from_string(kv.second.Scalar());
        } catch (const GraphError& e) {
          fail(kv.second, e.what());
        }
      } else if (key == "capacity") {
        const auto v = option_from_yaml(kv.second, file, "live capacity");
        if (!std::holds_alternative<long long>(v) || std::get<long long>(v) < 1)
          fail(kv.second, "live 'capacity' must be a whole number >= 1");
        capacity = std::size_t(std::get<long long>(v));
      } else {
        fail(kv.first, "unknown field '" + key + "' in 'live' (fields: overflow, capacity)");
      }
    }
    set_overflow(policy, capacity);
  }
}

Graph Graph::load(const std::string& path) {
  bool ok = false;
  const std::string text = read_file(path, &ok);
  if (!ok) throw GraphError(path + ": cannot open the graph file");
  return parse(text, path);
}

std::string Graph::to_yaml() const {
  std::ostringstream s;
  s << "# mereo graph (see graphs/README.md)\nnodes:\n";
  for (const auto& n : nodes_) {
    if (n.custom) throw GraphError("node '" + n.name + "' is a Python/custom node and cannot be saved to a file");
    s << "  - name: " << n.name << "\n    kind: " << n.kind << "\n";
    if (!n.given.empty()) {
      s << "    options: {";
      bool first = true;
      for (const auto& [k, v] : n.options.values()) {
        if (!n.given.count(k)) continue;
        s << (first ? "" : ", ") << k << ": " << yaml_value(v);
        first = false;
      }
      s << "}\n";
    }
  }
  s << "edges:\n";
  for (const auto& e : edges_)
    s << "  - " << e.from_node << "." << e.from_port << " -> " << e.to_node << "." << e.to_port << "\n";
  if (overflow_ != Overflow::Block || overflow_capacity_ != 2)
    s << "live: {overflow: " << to_string(overflow_) << ", capacity: " << overflow_capacity_ << "}\n";
  return s.str();
}

void Graph::save(const std::string& path) const {
  const std::string text = to_yaml();
  std::ofstream out(path);
  if (!out) throw GraphError(path + ": cannot write the graph file");
  out << text;
}

std::string Graph::to_dot() const {
  std::ostringstream s;
  s << "digraph mereo {\n  rankdir=LR;\n  node [shape=box, style=\"rounded,filled\", fillcolor=\"#eef3fb\", "
       "fontname=\"Helvetica\"];\n  edge [fontname=\"Helvetica\", fontsize=10];\n";
  for (const auto& n : nodes_) {
    s << "  \"" << n.name << "\" [label=<<b>" << n.name << "</b><br/><font point-size=\"10\">" << n.kind;
    for (const auto& [k, v] : n.options.values())
      if (n.given.count(k)) s << "<br/>" << k << "=" << std::visit([](const auto& x) {
        std::ostringstream t;
        t << std::boolalpha << x;
        return t.str();
      }, v);
    s << "</font>>";
    if (n.spec().is_source) s << ", fillcolor=\"#dff0d8\"";
    if (n.spec().constant) s << ", fillcolor=\"#fbeed5\"";
    s << "];\n";
  }
  for (const auto& e : edges_)
    s << "  \"" << e.from_node << "\" -> \"" << e.to_node << "\" [label=\"" << e.from_port
      << (e.from_port == e.to_port ? std::string() : " > " + e.to_port) << "\"];\n";
  s << "}\n";
  return s.str();
}

}  // namespace mereo::graph
