// YAML model files (see model_file.hpp); errors name the file, the line and the field.
#include "mereo/knowledge/model_file.hpp"

#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "mereo/core/error.hpp"

namespace mereo::knowledge {
namespace {

struct Reader {
  std::string file;

  std::string at(const YAML::Node& n) const {
    return file + ":" + std::to_string(n.Mark().line + 1) + ":" + std::to_string(n.Mark().column + 1);
  }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& field, const std::string& what) const {
    throw InputError(at(n) + ": field " + printable(field) + ": " + what);
  }
  /// A scalar's text (a key, a role, a name); a list or mapping where text belongs is named.
  std::string scalar(const YAML::Node& n, const std::string& field) const {
    if (!n.IsScalar()) fail(n, field, n.IsSequence() ? "expected a text, got a list" : "expected a text, got a mapping");
    return n.Scalar();
  }
  /// Rejects keys outside `allowed`, naming the misspelt one and the allowed ones.
  void check_keys(const YAML::Node& map, const std::set<std::string>& allowed, const std::string& what) const {
    if (!map.IsMap()) throw InputError(at(map) + ": " + what + ": expected a mapping");
    for (const auto& kv : map) {
      const std::string key = scalar(kv.first, "(a key in " + what + ")");
      if (!allowed.count(key)) {
        std::string known;
        for (const auto& k : allowed) known += (known.empty() ? "" : ", ") + k;
        fail(kv.first, key, "unknown field in " + what + " (known: " + known + ")");
      }
    }
  }
  std::string text(const YAML::Node& map, const std::string& key, bool required = true) const {
    const YAML::Node n = map[key];
    if (!n) {
      if (required) throw InputError(at(map) + ": field '" + key + "': missing");
      return {};
    }
    return scalar(n, key);
  }
  double number(const YAML::Node& n, const std::string& key) const {
    try {
      return n.as<double>();
    } catch (const YAML::Exception&) {
      fail(n, key, "expected a number, got " + (n.IsScalar() ? printable(n.Scalar()) : std::string("a list or mapping")));
    }
  }
  bool flag(const YAML::Node& n, const std::string& key) const {
    try {
      return n.as<bool>();
    } catch (const YAML::Exception&) {
      fail(n, key, "expected true or false");
    }
  }
  std::pair<double, double> pair(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence() || n.size() != 2) fail(n, key, "expected [P(x | concept), P(x | not concept)]");
    const double a = number(n[0], key), b = number(n[1], key);
    if (a < 0 || a > 1 || b < 0 || b > 1) fail(n, key, "probabilities must lie in [0, 1]");
    return {a, b};
  }

  Part part(const YAML::Node& n) const {
    check_keys(n, {"role", "class", "optional", "detail", "missing_score", "group"}, "a part");
    Part p;
    p.origin = at(n);
    p.role = text(n, "role");
    p.cls = text(n, "class");
    p.group = text(n, "group", false);
    if (n["optional"]) p.optional = flag(n["optional"], "optional");
    if (n["missing_score"]) {
      p.missing_score = number(n["missing_score"], "missing_score");
      if (p.missing_score < 0 || p.missing_score > 1) fail(n["missing_score"], "missing_score", "must lie in [0, 1]");
    }
    if (n["detail"]) {
      const std::string d = text(n, "detail");
      if (d == "coarse") p.detail = Detail::Coarse;
      else if (d == "fine") p.detail = Detail::Fine;
      else fail(n["detail"], "detail", "expected coarse or fine, got " + printable(d));
    }
    return p;
  }

  Attribute attribute(const YAML::Node& n) const {
    check_keys(n, {"part", "attribute", "range", "margin", "at_most", "at_least"}, "an attribute");
    Attribute a;
    a.origin = at(n);
    a.part = text(n, "part");
    a.name = text(n, "attribute");
    const double margin = n["margin"] ? number(n["margin"], "margin") : 0.0;
    if (margin < 0) fail(n["margin"], "margin", "must be >= 0");
    if (n["range"]) {
      const YAML::Node r = n["range"];
      if (!r.IsSequence() || r.size() != 2) fail(r, "range", "expected [lo, hi]");
      const double lo = number(r[0], "range"), hi = number(r[1], "range");
      if (lo > hi) fail(r, "range", "lo > hi");
      a.range = Membership::range(lo, hi, margin);
    } else if (n["at_most"]) {
      const double v = number(n["at_most"], "at_most");
      a.range = Membership::at_most(v, v + margin);
    } else if (n["at_least"]) {
      const double v = number(n["at_least"], "at_least");
      a.range = Membership::at_least(v - margin, v);
    } else {
      throw InputError(at(n) + ": field 'range': missing (range, at_most or at_least)");
    }
    return a;
  }

  Constraint constraint(const YAML::Node& n) const {
    if (!n.IsMap()) throw InputError(at(n) + ": a constraint: expected a mapping");
    Constraint c;
    c.origin = at(n);
    c.predicate = text(n, "predicate");
    const YAML::Node parts = n["parts"];
    if (!parts) throw InputError(at(n) + ": field 'parts': missing");
    if (!parts.IsSequence()) fail(parts, "parts", "expected a list of roles");
    for (const auto& r : parts) c.parts.push_back(scalar(r, "parts"));
    for (const auto& kv : n) {
      const std::string key = scalar(kv.first, "(a key in a constraint)");
      if (key == "predicate" || key == "parts") continue;
      c.params[key] = number(kv.second, key);  // names are checked against the predicate later
    }
    return c;
  }

  Concept concept_(const YAML::Node& n) const {
    check_keys(n, {"name", "parent", "description", "parts", "attributes", "constraints", "modalities", "bayes"},
               "a concept");
    Concept c;
    c.origin = at(n);
    c.name = text(n, "name");
    c.parent = text(n, "parent", false);
    c.description = text(n, "description", false);
    auto list = [&](const char* key) {
      const YAML::Node l = n[key];
      if (l && !l.IsSequence()) fail(l, key, "expected a list");
      return l;
    };
    if (auto l = list("parts")) for (const auto& p : l) c.parts.push_back(part(p));
    if (auto l = list("attributes")) for (const auto& a : l) c.attributes.push_back(attribute(a));
    if (auto l = list("constraints")) for (const auto& k : l) c.constraints.push_back(constraint(k));
    if (auto l = list("modalities"))
      for (const auto& m : l) {
        check_keys(m, {"name", "parts"}, "a modality");
        Modality mod;
        mod.name = text(m, "name");
        if (!m["parts"] || !m["parts"].IsSequence()) fail(m, "parts", "expected a list of roles");
        for (const auto& r : m["parts"]) mod.parts.push_back(scalar(r, "parts"));
        c.modalities.push_back(mod);
      }
    if (const YAML::Node b = n["bayes"]) {
      check_keys(b, {"prior", "present_obligatory", "present_optional", "quality", "satisfied"}, "bayes");
      if (b["prior"]) {
        c.bayes.prior = number(b["prior"], "prior");
        if (!(c.bayes.prior > 0 && c.bayes.prior < 1)) fail(b["prior"], "prior", "must lie in (0, 1)");
      }
      if (b["present_obligatory"]) c.bayes.present_obligatory = pair(b["present_obligatory"], "present_obligatory");
      if (b["present_optional"]) c.bayes.present_optional = pair(b["present_optional"], "present_optional");
      if (b["quality"]) c.bayes.quality = pair(b["quality"], "quality");
      if (b["satisfied"]) c.bayes.satisfied = pair(b["satisfied"], "satisfied");
    }
    return c;
  }
};

}  // namespace

void parse_models(KnowledgeBase& kb, const std::string& yaml_text, const std::string& file_name) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(file_name + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + printable(e.msg, 200));
  }
  const Reader r{file_name};
  if (!root || !root.IsMap()) throw InputError(file_name + ": expected a mapping with 'concepts'");
  r.check_keys(root, {"concepts"}, "a model file");
  const YAML::Node list = root["concepts"];
  if (!list || !list.IsSequence()) throw InputError(file_name + ": field 'concepts': expected a list");
  KnowledgeBase next = kb;
  std::map<std::string, std::string> defined;  // name -> where, in this file
  try {
    for (const auto& n : list) {
      Concept c = r.concept_(n);
      if (const auto [it, fresh] = defined.emplace(c.name, c.origin); !fresh)
        throw InputError(c.origin + ": concept " + printable(c.name) + " is defined twice in this file (first at " +
                         it->second + ")");
      next.add(std::move(c));
    }
  } catch (const YAML::Exception& e) {  // a shape the checks above did not foresee
    throw InputError(file_name + ":" + std::to_string(e.mark.line + 1) + ": " + printable(e.msg, 200));
  }
  next.validate();  // errors carry the origins (file:line:column) recorded above
  kb = std::move(next);
}

const std::vector<std::pair<std::string, std::string>>& builtin_model_files();  // generated

const KnowledgeBase& builtin_models() {
  static const KnowledgeBase kb = [] {
    KnowledgeBase k;
    for (const auto& [name, text] : builtin_model_files()) parse_models(k, text, name);
    return k;
  }();
  return kb;
}

KnowledgeBase models_from(const std::string& spec) {
  if (spec.empty()) return builtin_models();
  KnowledgeBase kb = builtin_models();  // a file may specialize the shipped concepts
  load_models(kb, spec);
  return kb;
}

void load_models(KnowledgeBase& kb, const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the model file");
  std::stringstream ss;
  ss << in.rdbuf();
  parse_models(kb, ss.str(), path);
}

}  // namespace mereo::knowledge
