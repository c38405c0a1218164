#include "mereo/graph/node.hpp"

#include <cmath>
#include <deque>
#include <mutex>
#include <sstream>

#include "mereo/graph/graph.hpp"

namespace mereo::graph {

const char* to_string(OptionType t) {
  switch (t) {
    case OptionType::Bool: return "bool";
    case OptionType::Int: return "int";
    case OptionType::Double: return "float";
    case OptionType::String: return "str";
  }
  return "?";
}

const OptionValue& Options::at(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw std::logic_error("no option '" + name + "'");
  return it->second;
}
bool Options::get_bool(const std::string& name) const { return std::get<bool>(at(name)); }
long long Options::get_int(const std::string& name) const { return std::get<long long>(at(name)); }
double Options::get_double(const std::string& name) const {
  const auto& v = at(name);
  if (auto* i = std::get_if<long long>(&v)) return double(*i);
  return std::get<double>(v);
}
const std::string& Options::get_string(const std::string& name) const { return std::get<std::string>(at(name)); }

const PortSpec* NodeSpec::input(const std::string& name) const {
  for (const auto& p : inputs)
    if (p.name == name) return &p;
  return nullptr;
}
const PortSpec* NodeSpec::output(const std::string& name) const {
  for (const auto& p : outputs)
    if (p.name == name) return &p;
  return nullptr;
}
const OptionSpec* NodeSpec::option(const std::string& name) const {
  for (const auto& o : options)
    if (o.name == name) return &o;
  return nullptr;
}

namespace {

std::string value_text(const OptionValue& v) {
  std::ostringstream s;
  std::visit([&](const auto& x) {
    if constexpr (std::is_same_v<std::decay_t<decltype(x)>, bool>) s << (x ? "true" : "false");
    else if constexpr (std::is_same_v<std::decay_t<decltype(x)>, std::string>) s << "'" << x << "'";
    else s << x;
  }, v);
  return s.str();
}

std::string names_of(const std::vector<OptionSpec>& options) {
  std::string out;
  for (const auto& o : options) out += (out.empty() ? "" : ", ") + o.name;
  return out.empty() ? "none" : out;
}

}  // namespace

Options NodeSpec::validate(const std::string& node_name, const std::map<std::string, OptionValue>& given) const {
  std::map<std::string, OptionValue> values;
  for (const auto& o : options) values[o.name] = o.default_value;
  for (const auto& [name, v] : given) {
    const OptionSpec* o = option(name);
    const std::string where = "node '" + node_name + "' (" + kind + "): option '" + name + "'";
    if (!o) throw GraphError(where + " does not exist (options: " + names_of(options) + ")");
    OptionValue value = v;
    // Integers are accepted where reals are wanted; integral reals where integers are.
    if (o->type == OptionType::Double && std::holds_alternative<long long>(v))
      value = double(std::get<long long>(v));
    if (o->type == OptionType::Int && std::holds_alternative<double>(v)) {
      const double x = std::get<double>(v);
      if (x == std::floor(x) && std::abs(x) < 9e15) value = static_cast<long long>(x);
    }
    const bool type_ok = (o->type == OptionType::Bool && std::holds_alternative<bool>(value)) ||
                         (o->type == OptionType::Int && std::holds_alternative<long long>(value)) ||
                         (o->type == OptionType::Double && std::holds_alternative<double>(value)) ||
                         (o->type == OptionType::String && std::holds_alternative<std::string>(value));
    if (!type_ok)
      throw GraphError(where + " must be " + to_string(o->type) + ", got " + value_text(v));
    if (o->type == OptionType::Int || o->type == OptionType::Double) {
      const double x = o->type == OptionType::Int ? double(std::get<long long>(value)) : std::get<double>(value);
      if (!(x >= o->min && x <= o->max)) {
        std::ostringstream s;
        s << where << " = " << value_text(value) << " is outside its range [" << o->min << ", " << o->max << "]";
        throw GraphError(s.str());
      }
    }
    if (o->type == OptionType::String && !o->choices.empty()) {
      const auto& x = std::get<std::string>(value);
      bool found = false;
      std::string list;
      for (const auto& c : o->choices) {
        found |= c == x;
        list += (list.empty() ? "" : ", ") + c;
      }
      if (!found) throw GraphError(where + " = '" + x + "' is not one of: " + list);
    }
    values[name] = value;
  }
  return Options(std::move(values));
}

namespace {
struct SpecRegistry {
  std::mutex mutex;
  std::deque<NodeSpec> specs;  // deque: references stay valid as kinds are added
};
SpecRegistry& spec_registry() {
  static SpecRegistry* r = new SpecRegistry;  // never destroyed: usable until the process ends
  return *r;
}
}  // namespace

std::vector<NodeSpec> node_specs() {
  auto& r = spec_registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  return {r.specs.begin(), r.specs.end()};
}

const NodeSpec& node_spec(const std::string& kind) {
  auto& r = spec_registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::string known;
  for (const auto& s : r.specs) {
    if (s.kind == kind) return s;
    known += (known.empty() ? "" : ", ") + s.kind;
  }
  if (known.empty())
    throw GraphError("unknown node kind '" + kind +
                     "' (no kinds are registered; mereo's: call mereo::nodes::register_builtin() first)");
  throw GraphError("unknown node kind '" + kind + "' (known: " + known + ")");
}

void register_node(NodeSpec spec) {
  auto& r = spec_registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& s : r.specs)
    if (s.kind == spec.kind) throw GraphError("node kind '" + spec.kind + "' is registered already");
  r.specs.push_back(std::move(spec));
}

}  // namespace mereo::graph
