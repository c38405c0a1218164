// The knowledge base: concepts, specialization, checks (see model.hpp).
#include "mereo/knowledge/model.hpp"
#include "mereo/shapes/table.hpp"

#include <algorithm>
#include <set>

#include "mereo/core/error.hpp"
#include "mereo/knowledge/predicates.hpp"

namespace mereo::knowledge {
namespace {

std::string where(const std::string& origin, const std::string& fallback) {
  return origin.empty() ? fallback : origin;
}

}  // namespace

const char* to_string(Detail d) { return d == Detail::Coarse ? "coarse" : "fine"; }

bool is_primitive(const std::string& cls) {
  static const std::vector<std::string> names = primitive_class_names();  // the shape table's
  return std::find(names.begin(), names.end(), cls) != names.end();
}

double Constraint::param(const std::string& name, double fallback) const {
  const auto it = params.find(name);
  return it == params.end() ? fallback : it->second;
}

const Part* Concept::part(const std::string& role) const {
  for (const auto& p : parts)
    if (p.role == role) return &p;
  return nullptr;
}
int Concept::part_index(const std::string& role) const {
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (parts[i].role == role) return int(i);
  return -1;
}

void KnowledgeBase::add(Concept c) {
  const std::string name = c.name;
  concepts_[name] = std::move(c);
}
bool KnowledgeBase::has(const std::string& name) const { return concepts_.count(name) > 0; }
const Concept& KnowledgeBase::get(const std::string& name) const {
  const auto it = concepts_.find(name);
  if (it == concepts_.end()) {
    std::string known;
    for (const auto& [k, v] : concepts_) known += (known.empty() ? "" : ", ") + k;
    throw InputError("unknown concept '" + name + "' (known: " + known + ")");
  }
  return it->second;
}
std::vector<std::string> KnowledgeBase::names() const {
  std::vector<std::string> out;
  for (const auto& [k, v] : concepts_) out.push_back(k);
  return out;
}

bool KnowledgeBase::is_a(const std::string& cls, const std::string& ancestor) const {
  std::string c = cls;
  for (int depth = 0; depth < 64 && !c.empty(); ++depth) {
    if (c == ancestor) return true;
    if (!has(c)) return false;
    c = concepts_.at(c).parent;
  }
  return false;
}

std::vector<std::string> KnowledgeBase::ancestors(const std::string& cls) const {
  std::vector<std::string> out;
  for (std::string c = has(cls) ? concepts_.at(cls).parent : ""; !c.empty() && has(c) && out.size() < 64;
       c = concepts_.at(c).parent)
    out.push_back(c);
  return out;
}

Concept KnowledgeBase::resolve(const std::string& name) const {
  // the chain of ancestors, checked for cycles
  std::vector<const Concept*> chain;
  std::set<std::string> seen;
  for (std::string n = name; !n.empty();) {
    const Concept& c = get(n);
    if (!seen.insert(n).second)
      throw InputError(where(c.origin, "concept " + n) + ": specialization cycle through '" + n + "'");
    chain.push_back(&c);
    if (!c.parent.empty() && !has(c.parent))
      throw InputError(where(c.origin, "concept " + n) + ": field 'parent': unknown concept '" + c.parent + "'");
    n = c.parent;
  }
  std::reverse(chain.begin(), chain.end());
  Concept out;
  for (const Concept* c : chain) {
    const std::string at = where(c->origin, "concept " + c->name);
    for (const Part& p : c->parts) {
      if (!is_primitive(p.cls) && !has(p.cls))
        throw InputError(where(p.origin, at) + ": field 'class': unknown class '" + p.cls + "' of part '" +
                         p.role + "' (a primitive: plane, cylinder, torus, sphere, line, arc, or a concept)");
      const int i = out.part_index(p.role);
      if (i < 0) {
        out.parts.push_back(p);
        continue;
      }
      // a part given again in a specialization narrows the inherited one
      if (c == chain.front() || !(p.cls == out.parts[i].cls || is_a(p.cls, out.parts[i].cls)))
        throw InputError(where(p.origin, at) + ": field 'role': part '" + p.role + "' is defined twice");
      out.parts[i] = p;
    }
    for (const Attribute& a : c->attributes) {
      const std::string aw = where(a.origin, at);
      if (out.part_index(a.part) < 0)
        throw InputError(aw + ": field 'part': no part '" + a.part + "' in concept '" + c->name + "'");
      if (!is_attribute(a.name)) {
        std::string known;
        for (const auto& n : attribute_names()) known += (known.empty() ? "" : ", ") + n;
        throw InputError(aw + ": field 'attribute': unknown attribute '" + a.name + "' (known: " + known + ")");
      }
      if (!(a.range.a <= a.range.b && a.range.b <= a.range.c && a.range.c <= a.range.d))
        throw InputError(aw + ": field 'range': not a valid range " + a.range.str());
      auto it = std::find_if(out.attributes.begin(), out.attributes.end(),
                             [&](const Attribute& x) { return x.part == a.part && x.name == a.name; });
      if (it == out.attributes.end()) {
        out.attributes.push_back(a);
      } else {
        if (!a.range.within(it->range))
          throw InputError(aw + ": field 'range': " + a.part + "." + a.name + " " + a.range.str() +
                           " widens the inherited " + it->range.str() + " (a specialization may only narrow)");
        *it = a;
      }
    }
    for (const Constraint& k : c->constraints) {
      const std::string kw = where(k.origin, at);
      if (!k.custom && !is_builtin_predicate(k.predicate)) {
        std::string known;
        for (const auto& n : builtin_predicates()) known += (known.empty() ? "" : ", ") + n;
        throw InputError(kw + ": field 'predicate': unknown predicate '" + k.predicate + "' (known: " + known + ")");
      }
      if (k.parts.size() < 2)
        throw InputError(kw + ": field 'parts': a constraint relates two or more parts");
      for (const auto& r : k.parts)
        if (out.part_index(r) < 0)
          throw InputError(kw + ": field 'parts': no part '" + r + "' in concept '" + c->name + "'");
      if (!k.custom)
        for (const auto& [pname, v] : k.params) {
          const auto& ok = predicate_params(k.predicate);
          if (std::find(ok.begin(), ok.end(), pname) == ok.end()) {
            std::string known;
            for (const auto& n : ok) known += (known.empty() ? "" : ", ") + n;
            throw InputError(kw + ": field '" + pname + "': predicate '" + k.predicate + "' has no parameter '" +
                             pname + "' (known: " + known + ")");
          }
        }
      auto it = std::find_if(out.constraints.begin(), out.constraints.end(), [&](const Constraint& x) {
        return x.predicate == k.predicate && x.parts == k.parts;
      });
      if (it == out.constraints.end())
        out.constraints.push_back(k);
      else
        *it = k;
    }
    for (const Modality& m : c->modalities) {
      for (const auto& r : m.parts)
        if (out.part_index(r) < 0)
          throw InputError(at + ": field 'modalities': modality '" + m.name + "' names no part '" + r + "'");
      auto it = std::find_if(out.modalities.begin(), out.modalities.end(),
                             [&](const Modality& x) { return x.name == m.name; });
      if (it == out.modalities.end())
        out.modalities.push_back(m);
      else
        *it = m;
    }
    out.name = c->name;
    out.parent = c->parent;
    out.description = c->description.empty() ? out.description : c->description;
    out.bayes = c->bayes;
    out.origin = c->origin;
  }
  for (const Part& p : out.parts)
    for (const Part& q : out.parts)
      if (!p.group.empty() && p.group == q.group && p.cls != q.cls)
        throw InputError(where(q.origin, "concept " + name) + ": field 'group': parts '" + p.role + "' and '" + q.role +
                         "' of group '" + p.group + "' differ in class");
  if (out.parts.empty()) throw InputError(where(out.origin, "concept " + name) + ": concept '" + name + "' has no parts");
  return out;
}

void KnowledgeBase::validate() const {
  for (const auto& [name, c] : concepts_) resolve(name);
}

Concept select(const Concept& resolved, const std::string& modality, Detail detail) {
  std::set<std::string> keep;
  if (resolved.modalities.empty()) {
    if (!modality.empty()) throw InputError("concept '" + resolved.name + "' has no modality '" + modality + "'");
    for (const auto& p : resolved.parts) keep.insert(p.role);
  } else {
    const Modality* m = &resolved.modalities.front();
    if (!modality.empty()) {
      m = nullptr;
      for (const auto& x : resolved.modalities)
        if (x.name == modality) m = &x;
      if (!m) throw InputError("concept '" + resolved.name + "' has no modality '" + modality + "'");
    }
    keep.insert(m->parts.begin(), m->parts.end());
  }
  Concept out = resolved;
  out.parts.clear();
  for (const auto& p : resolved.parts)
    if (keep.count(p.role) && (detail == Detail::Fine || p.detail == Detail::Coarse)) out.parts.push_back(p);
  auto kept = [&](const std::string& role) { return out.part_index(role) >= 0; };
  out.attributes.clear();
  for (const auto& a : resolved.attributes)
    if (kept(a.part)) out.attributes.push_back(a);
  out.constraints.clear();
  for (const auto& k : resolved.constraints)
    if (std::all_of(k.parts.begin(), k.parts.end(), kept)) out.constraints.push_back(k);
  return out;
}

}  // namespace mereo::knowledge
