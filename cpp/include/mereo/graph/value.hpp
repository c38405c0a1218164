// mereo/graph/value.hpp: the typed values that travel along a graph's edges.
//
// A Value is an immutable, shared, type-tagged object (a Frame, a Cloud, a list of Segments,
// a number...). Copies are cheap (a shared_ptr). Each C++ type that may cross an edge is
// registered once with a port-type name: the engine's own "Number" (double) and "Text"
// (std::string); a library registers its types with register_type (mereo's: "Frame",
// "Cloud", ..., in mereo::nodes::register_builtin). Ports declare these names and verify()
// compares them.
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <typeindex>
#include <vector>

namespace mereo::graph {

/// A registered port type: its name and how to summarise a value of it in one line.
struct TypeInfo {
  std::string name;
  std::type_index type = typeid(void);
  std::function<std::string(const void*)> describe;  ///< one-line summary ("640x480 cloud")
};

/// The first type registered for C++ type T (several names may share one C++ type, e.g.
/// "Cloud" and "NormalMap"); throws std::logic_error if T was never registered.
const TypeInfo& type_of(std::type_index t);
template <typename T>
const TypeInfo& type_of() { return type_of(std::type_index(typeid(T))); }
/// The registered type named `name`, or nullptr.
const TypeInfo* find_type(const std::string& name);
/// Every registered type name, sorted.
std::vector<std::string> type_names();
/// Registers T under `name` (idempotent; thread-safe). `describe` may be empty.
void register_type(const std::string& name, std::type_index t,
                   std::function<std::string(const void*)> describe = {});
template <typename T>
void register_type(const std::string& name, std::function<std::string(const T&)> describe = {}) {
  register_type(name, std::type_index(typeid(T)),
                describe ? std::function<std::string(const void*)>(
                               [describe](const void* p) { return describe(*static_cast<const T*>(p)); })
                         : std::function<std::string(const void*)>());
}

class Value {
 public:
  Value() = default;
  template <typename T>
  static Value make(T value) {
    Value v;
    v.type_ = &type_of<T>();
    v.ptr_ = std::make_shared<const T>(std::move(value));
    return v;
  }
  /// The same object under another registered name of the same C++ type (a port's type);
  /// throws std::logic_error if the C++ types differ.
  Value as(const TypeInfo& type) const;
  bool empty() const { return !ptr_; }
  const TypeInfo& type() const { return *type_; }
  /// The value as T; throws std::logic_error naming both types if it holds another type.
  template <typename T>
  const T& get() const {
    if (!ptr_) throw std::logic_error("empty value read as " + type_of<T>().name);
    if (type_->type != std::type_index(typeid(T)))
      throw std::logic_error("a value of type " + type_->name + " read as " + type_of<T>().name);
    return *static_cast<const T*>(ptr_.get());
  }
  const void* raw() const { return ptr_.get(); }
  std::string describe() const;

 private:
  const TypeInfo* type_ = nullptr;
  std::shared_ptr<const void> ptr_;
};

}  // namespace mereo::graph
