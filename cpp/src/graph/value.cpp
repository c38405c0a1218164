#include "mereo/graph/value.hpp"

#include <algorithm>
#include <deque>
#include <mutex>
#include <sstream>

namespace mereo::graph {

namespace {

struct Registry {
  std::mutex mutex;
  std::deque<TypeInfo> types;  // deque: stable addresses
};

void register_builtin(Registry& r);

Registry& registry() {
  static Registry* r = [] {
    auto* reg = new Registry;
    register_builtin(*reg);
    return reg;
  }();
  return *r;
}

void add(Registry& r, const std::string& name, std::type_index t, std::function<std::string(const void*)> d) {
  for (auto& e : r.types)
    if (e.name == name) {
      if (e.type != t) throw std::logic_error("port type '" + name + "' registered for two C++ types");
      return;
    }
  r.types.push_back({name, t, std::move(d)});
}

template <typename T>
void add(Registry& r, const std::string& name, std::function<std::string(const T&)> d) {
  add(r, name, std::type_index(typeid(T)), [d](const void* p) { return d(*static_cast<const T*>(p)); });
}

// The engine's own port types; a library registers its types with register_type (mereo's in
// mereo::nodes::register_builtin).
void register_builtin(Registry& r) {
  add<double>(r, "Number", [](const double& x) {
    std::ostringstream s;
    s.precision(17);
    s << x;
    return s.str();
  });
  add<std::string>(r, "Text", [](const std::string& x) { return x; });
}

}  // namespace

const TypeInfo& type_of(std::type_index t) {
  auto& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& e : r.types)
    if (e.type == t) return e;
  throw std::logic_error(std::string("C++ type ") + t.name() +
                         " is not a registered port type (register_type; mereo's types: mereo::nodes::register_builtin())");
}

const TypeInfo* find_type(const std::string& name) {
  auto& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& e : r.types)
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> type_names() {
  auto& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& e : r.types) names.push_back(e.name);
  std::sort(names.begin(), names.end());
  return names;
}

void register_type(const std::string& name, std::type_index t, std::function<std::string(const void*)> d) {
  auto& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  add(r, name, t, std::move(d));
}

Value Value::as(const TypeInfo& type) const {
  if (!type_ || type.type != type_->type)
    throw std::logic_error("a value of type " + (type_ ? type_->name : std::string("(empty)")) +
                           " cannot pass as " + type.name);
  Value v = *this;
  v.type_ = &type;
  return v;
}

std::string Value::describe() const {
  if (!ptr_) return "(empty)";
  return type_->describe ? type_->describe(ptr_.get()) : type_->name;
}

}  // namespace mereo::graph
