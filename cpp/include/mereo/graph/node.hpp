// mereo/graph/node.hpp: what a node declares (ports, options, doc) and what its body sees.
//
// A node kind is a NodeSpec: typed input and output ports, typed options (name, type,
// default, allowed range, one-line doc) and a factory that turns option values into a body.
// The body calls one plain algorithm function. The engine knows no kinds of its own: a library
// registers its kinds explicitly (mereo's in one list, mereo::nodes::register_builtin); Python
// sees each of them through one generic binder.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "mereo/graph/value.hpp"

namespace mereo::graph {

struct PortSpec {
  std::string name;
  std::string type;       ///< a registered type name (value.hpp)
  std::string doc;
  bool required = true;   ///< inputs only: verify() rejects an unconnected required input
};

/// An option's value: bool, integer, real or text.
using OptionValue = std::variant<bool, long long, double, std::string>;
enum class OptionType { Bool, Int, Double, String };
const char* to_string(OptionType t);

struct OptionSpec {
  std::string name;
  OptionType type = OptionType::Double;
  OptionValue default_value = 0.0;
  double min = -1e300;              ///< Int and Double: allowed range (inclusive)
  double max = 1e300;
  std::vector<std::string> choices; ///< String: allowed values (empty = any)
  std::string doc;
};

/// Option values of one node, by name (every option present after validation).
class Options {
 public:
  Options() = default;
  explicit Options(std::map<std::string, OptionValue> values) : values_(std::move(values)) {}
  bool get_bool(const std::string& name) const;
  long long get_int(const std::string& name) const;
  double get_double(const std::string& name) const;  ///< also reads Int options
  const std::string& get_string(const std::string& name) const;
  const std::map<std::string, OptionValue>& values() const { return values_; }
  void set(const std::string& name, OptionValue v) { values_[name] = std::move(v); }

 private:
  const OptionValue& at(const std::string& name) const;
  std::map<std::string, OptionValue> values_;
};

/// What a node body reads and writes for one frame.
class NodeContext {
 public:
  virtual ~NodeContext() = default;
  /// The value on input `port` (throws std::logic_error if unconnected or of another type).
  template <typename T>
  const T& input(const std::string& port) const { return input_value(port).get<T>(); }
  /// False for an optional input that is not connected.
  virtual bool has_input(const std::string& port) const = 0;
  virtual const Value& input_value(const std::string& port) const = 0;
  template <typename T>
  void output(const std::string& port, T value) { set_output(port, Value::make<T>(std::move(value))); }
  virtual void set_output(const std::string& port, Value v) = 0;
  /// Position of the frame in the run (0, 1, ...) and its id.
  virtual std::size_t frame_index() const = 0;
  virtual const std::string& frame_id() const = 0;
};

/// A node body: reads inputs, calls one algorithm function, writes outputs. It must be
/// safe to call concurrently for different frames unless the spec says `serial`.
using NodeBody = std::function<void(NodeContext&)>;

struct NodeSpec {
  std::string kind;                   ///< "back_project", "estimate_normals", ...
  std::string doc;                    ///< one paragraph; the first line is the summary
  std::vector<PortSpec> inputs;
  std::vector<PortSpec> outputs;
  std::vector<OptionSpec> options;
  std::function<NodeBody(const Options&)> make;
  bool serial = false;                ///< at most one frame at a time (stateful nodes, Python)
  /// Frames one at a time and in their order, in both modes (nodes that track across frames);
  /// implies serial.
  bool ordered = false;
  bool is_source = false;             ///< fed by the run's frame source (frame_source only)
  /// No inputs: runs once per run, before the first frame, and its outputs feed every frame
  /// (the knowledge base of the `models` node).
  bool constant = false;

  const PortSpec* input(const std::string& name) const;
  const PortSpec* output(const std::string& name) const;
  const OptionSpec* option(const std::string& name) const;
  /// Fills defaults and checks every value's name, type and range; throws GraphError
  /// naming `node_name` and the option.
  Options validate(const std::string& node_name, const std::map<std::string, OptionValue>& given) const;
};

/// The registered node kinds, in the order of registration.
std::vector<NodeSpec> node_specs();
/// The spec of `kind`; throws GraphError listing the known kinds.
const NodeSpec& node_spec(const std::string& kind);
/// Adds a kind (thread-safe); throws GraphError if the kind exists.
void register_node(NodeSpec spec);

}  // namespace mereo::graph
