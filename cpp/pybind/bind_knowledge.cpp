// The object layer: segments, object models (concepts, parts, attributes, constraints, the
// knowledge base, model files) and matching. Python-defined predicates are called with the GIL.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "converters.hpp"
#include "mereo/core/error.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/knowledge/bayes.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "mereo/knowledge/predicates.hpp"
#include "mereo/matching/interpret.hpp"
#include "mereo/matching/match.hpp"
#include "options.hpp"

namespace py = pybind11;
namespace kn = mereo::knowledge;
namespace mt = mereo::matching;
namespace pu = mereo::py_util;

void bind_knowledge(py::module_& m) {
  using mereo::Segment;
  // A field of the class (mereo/shapes/*.hpp) from Python: a number, a flag, a 3-vector or pixels.
  auto field_value = [](const std::string& name, const py::handle& v) -> mereo::shapes::FieldValue {
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
    if (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)) return v.cast<double>();
    if (py::hasattr(v, "__len__") && py::len(v) == 2) {  // pixels
      try {
        return v.cast<Eigen::Vector2d>();
      } catch (const py::cast_error&) {
      }
    } else {
      try {
        return v.cast<Eigen::Vector3d>();
      } catch (const py::cast_error&) {
      }
    }
    throw mereo::InputError("Segment field '" + name + "': expected a number, two numbers (pixels) or three");
  };
  auto make = [field_value](const std::string& cls, const py::dict& fields) {
    Segment s(mereo::primitive_class(cls).make());
    for (const auto& [key, value] : fields) {
      const auto name = key.cast<std::string>();
      if (name == "class" || name == "inliers" || name == "residual" || name == "hue" || name == "segment") continue;
      if (name == "inward") {
        s.inward = value.cast<bool>();
        continue;
      }
      if (!s.set_field(name, field_value(name, value))) {
        std::string known;
        for (const auto& [n, v] : s.fields()) known += (known.empty() ? "" : ", ") + std::string(n);
        throw mereo::InputError("a " + cls + " has no field '" + name + "' (its fields: " + known + ")");
      }
    }
    return s;
  };
  auto to_python = [](const mereo::shapes::FieldValue& v) {
    return std::visit([](const auto& x) { return py::cast(x); }, v);
  };
  py::class_<Segment>(m, "Segment",
                      "A primitive found in the data (a data instance): its class (one of the shape table's, "
                      "mereo/shapes/) with that class's parameters (metres, camera frame, the JSON output's "
                      "field names: a cylinder's point, axis, radius, height; a torus's center, normal, "
                      "major_radius, minor_radius...), inliers, residual, colour. Segment('cylinder', "
                      "point=..., axis=..., radius=..., height=...); a torus also takes point/axis/radius.")
      .def(py::init([make](const std::string& cls, const py::kwargs& fields) { return make(cls, fields); }),
           py::arg("cls"))
      .def_static("from_dict", [make](const py::dict& d) { return make(d["class"].cast<std::string>(), d); },
                  py::arg("d"), "A segment from a part or primitive of a result (its \"class\" and fields).")
      .def_property_readonly("cls", [](const Segment& s) { return std::string(s.class_name()); })
      .def_property_readonly("params",
                             [to_python](const Segment& s) {
                               py::dict d;
                               for (const auto& [name, v] : s.fields()) d[name] = to_python(v);
                               return d;
                             },
                             "the class's parameters, by their JSON names")
      .def("__getattr__",
           [to_python](const Segment& s, const std::string& name) -> py::object {
             for (const auto& [n, v] : s.fields())
               if (name == n) return to_python(v);
             if (auto v = s.attribute(name)) return py::cast(*v);  // aliases: a torus's radius...
             if (name == "point") return py::cast(s.origin());
             if (name == "axis")
               if (auto d = s.direction()) return py::cast(*d);
             throw py::attribute_error("a " + std::string(s.class_name()) + " segment has no '" + name + "'");
           })
      .def("set", [field_value](Segment& s, const std::string& name, const py::handle& v) {
             if (!s.set_field(name, field_value(name, v)))
               throw mereo::InputError("a " + std::string(s.class_name()) + " has no field '" + name + "'");
           }, py::arg("name"), py::arg("value"), "Sets one of the class's parameters by its JSON name.")
      .def_readwrite("id", &Segment::id)
      .def_readwrite("inliers", &Segment::inliers)
      .def_readwrite("residual", &Segment::residual)
      .def_readwrite("hue", &Segment::hue)
      .def_readwrite("inward", &Segment::inward, "seen from inside (a mug's inner wall)")
      .def_readwrite("end_closed", &Segment::end_closed,
                     "pixels whose rays stop on the end facing the camera (a lid; cylinders, cones)")
      .def_readwrite("end_open", &Segment::end_open,
                     "pixels whose rays pass the end facing the camera into the body (an open vessel)")
      .def_readwrite("bend", &Segment::bend,
                     "how much an axial body bends along its axis, as its normals show (1 / m; 0: none)")
      .def_readwrite("out_of_round", &Segment::out_of_round,
                     "how far an axial body's cross-section is from a circle (pattern RMS over radius; 0: none)")
      .def_property_readonly("pixels",
                             [](const Segment& s) {
                               py::array_t<int> a(py::ssize_t(s.pixels.size()));
                               std::copy(s.pixels.begin(), s.pixels.end(), a.mutable_data());
                               return a;
                             },
                             "inlier pixel indices v * width + u (NumPy int32)")
      .def_property_readonly("mean_color", [](const Segment& s) { return Eigen::Vector3f(s.mean_color); })
      .def("__repr__", [](const Segment& s) {
        std::string text = "<mereo.Segment " + std::string(s.class_name());
        for (const auto& [name, v] : s.fields())
          if (const auto* x = std::get_if<double>(&v)) text += " " + std::string(name) + "=" + std::to_string(*x);
        return text + ">";
      });
  m.def("primitive_classes", &mereo::primitive_class_names, "The shape table's classes, in its order.");

  py::class_<kn::Membership>(m, "Membership", "A trapezoidal fuzzy membership (a, b, c, d).")
      .def(py::init([](double a, double b, double c, double d) { return kn::Membership{a, b, c, d}; }))
      .def_static("range", &kn::Membership::range, py::arg("lo"), py::arg("hi"), py::arg("margin") = 0.0)
      .def_static("at_most", &kn::Membership::at_most, py::arg("full"), py::arg("zero"))
      .def_static("at_least", &kn::Membership::at_least, py::arg("zero"), py::arg("full"))
      .def("__call__", &kn::Membership::operator(), py::arg("x"))
      .def_readwrite("a", &kn::Membership::a)
      .def_readwrite("b", &kn::Membership::b)
      .def_readwrite("c", &kn::Membership::c)
      .def_readwrite("d", &kn::Membership::d)
      .def("__repr__", [](const kn::Membership& x) { return "Membership" + x.str(); });

  py::enum_<kn::Detail>(m, "Detail").value("coarse", kn::Detail::Coarse).value("fine", kn::Detail::Fine);
  py::class_<kn::Part>(m, "Part", "A part of a concept: a unique role and a class (a primitive or a concept).")
      .def(py::init([](std::string role, std::string cls, bool optional, double missing_score, kn::Detail detail,
                       std::string group) {
             kn::Part p;
             p.role = std::move(role), p.cls = std::move(cls), p.optional = optional;
             p.missing_score = missing_score, p.detail = detail, p.group = std::move(group);
             return p;
           }),
           py::arg("role"), py::arg("cls"), py::arg("optional") = false, py::arg("missing_score") = 0.5,
           py::arg("detail") = kn::Detail::Coarse, py::arg("group") = "")
      .def_readwrite("role", &kn::Part::role)
      .def_readwrite("cls", &kn::Part::cls)
      .def_readwrite("optional", &kn::Part::optional)
      .def_readwrite("missing_score", &kn::Part::missing_score)
      .def_readwrite("detail", &kn::Part::detail)
      .def_readwrite("group", &kn::Part::group);
  py::class_<kn::Attribute>(m, "Attribute", "A fuzzy range over one attribute of one part.")
      .def(py::init([](std::string part, std::string name, kn::Membership range) {
             return kn::Attribute{std::move(part), std::move(name), range, ""};
           }),
           py::arg("part"), py::arg("name"), py::arg("range"))
      .def_readwrite("part", &kn::Attribute::part)
      .def_readwrite("name", &kn::Attribute::name)
      .def_readwrite("range", &kn::Attribute::range);
  py::class_<kn::Context>(m, "Context").def(py::init<>()).def_readwrite("up", &kn::Context::up);
  py::class_<kn::Constraint>(m, "Constraint",
                             "A fuzzy relation between parts: a built-in predicate by name, or `custom`: a "
                             "Python callable (segments, constraint, context) -> value in [0, 1].")
      .def(py::init([](std::string predicate, std::vector<std::string> parts, std::map<std::string, double> params,
                       py::object custom) {
             kn::Constraint c;
             c.predicate = std::move(predicate), c.parts = std::move(parts), c.params = std::move(params);
             if (!custom.is_none()) {
               auto fn = std::make_shared<py::object>(custom);
               c.custom = [fn](const std::vector<const Segment*>& segs, const kn::Constraint& con,
                               const kn::Context& ctx) {
                 py::gil_scoped_acquire gil;
                 std::vector<Segment> copies;
                 for (const Segment* s : segs) copies.push_back(*s);
                 return (*fn)(copies, con, ctx).cast<double>();
               };
             }
             return c;
           }),
           py::arg("predicate"), py::arg("parts"), py::arg("params") = std::map<std::string, double>{},
           py::arg("custom") = py::none())
      .def_readwrite("predicate", &kn::Constraint::predicate)
      .def_readwrite("parts", &kn::Constraint::parts)
      .def_readwrite("params", &kn::Constraint::params);
  py::class_<kn::Modality>(m, "Modality")
      .def(py::init([](std::string name, std::vector<std::string> parts) { return kn::Modality{name, parts}; }),
           py::arg("name"), py::arg("parts"))
      .def_readwrite("name", &kn::Modality::name)
      .def_readwrite("parts", &kn::Modality::parts);
  py::class_<kn::Concept>(m, "Concept", "An object model: parts, attributes, constraints, modalities, a parent.")
      .def(py::init<>())
      .def_readwrite("name", &kn::Concept::name)
      .def_readwrite("parent", &kn::Concept::parent)
      .def_readwrite("description", &kn::Concept::description)
      .def_readwrite("parts", &kn::Concept::parts)
      .def_readwrite("attributes", &kn::Concept::attributes)
      .def_readwrite("constraints", &kn::Concept::constraints)
      .def_readwrite("modalities", &kn::Concept::modalities)
      .def_property("prior", [](const kn::Concept& c) { return c.bayes.prior; },
                    [](kn::Concept& c, double p) { c.bayes.prior = p; })
      .def("__repr__", [](const kn::Concept& c) {
        std::string parts;
        for (const auto& p : c.parts) parts += (parts.empty() ? "" : ", ") + p.role + ": " + p.cls;
        return "<mereo.Concept " + c.name + " (" + parts + ")>";
      });
  py::class_<kn::KnowledgeBase>(m, "KnowledgeBase", "Concepts and their specialization links.")
      .def(py::init<>())
      .def("add", &kn::KnowledgeBase::add, py::arg("concept"))
      .def("has", &kn::KnowledgeBase::has, py::arg("name"))
      .def("get", &kn::KnowledgeBase::get, py::arg("name"))
      .def("names", &kn::KnowledgeBase::names)
      .def("resolve", &kn::KnowledgeBase::resolve, py::arg("name"),
           "The concept with what it inherits; raises InputError naming the origin and field of a mistake.")
      .def("validate", &kn::KnowledgeBase::validate)
      .def("is_a", &kn::KnowledgeBase::is_a, py::arg("cls"), py::arg("ancestor"))
      .def("load", [](kn::KnowledgeBase& kb, const std::string& path) { kn::load_models(kb, path); }, py::arg("path"),
           "Adds the concepts of a YAML model file.")
      .def("parse", [](kn::KnowledgeBase& kb, const std::string& text, const std::string& name) {
             kn::parse_models(kb, text, name);
           }, py::arg("text"), py::arg("name") = "<text>");
  m.def("builtin_models", &kn::builtin_models, "The shipped models (graphs/models/*.yaml).");
  m.def("select", &kn::select, py::arg("concept"), py::arg("modality") = "", py::arg("detail") = kn::Detail::Fine,
        "One modality's parts at one level of detail, with their attributes and constraints.");

  py::class_<mt::Hypothesis>(m, "Hypothesis", "Segments assigned to a concept's parts (-1 = missing).")
      .def_readonly("concept", &mt::Hypothesis::concept_name)
      .def_readonly("modality", &mt::Hypothesis::modality, "the part set it was matched with (\"\" without alternatives)")
      .def_readonly("assignment", &mt::Hypothesis::assignment)
      .def_readonly("score", &mt::Hypothesis::score)
      .def_readonly("posterior", &mt::Hypothesis::posterior)
      .def_readonly("children", &mt::Hypothesis::children, "per part whose class is a concept: its sub-hypothesis")
      .def("__repr__", [](const mt::Hypothesis& h) {
        return "<mereo.Hypothesis " + h.concept_name + " score " + std::to_string(h.score) + ">";
      });
  py::class_<mt::MatchStats>(m, "MatchStats")
      .def_readonly("expanded", &mt::MatchStats::expanded)
      .def_readonly("pruned", &mt::MatchStats::pruned)
      .def_readonly("complete", &mt::MatchStats::complete);
  py::class_<mt::Lattice>(m, "Lattice", "Hypotheses and the exclusion arcs between those sharing a segment.")
      .def_readonly("hypotheses", &mt::Lattice::hypotheses)
      .def_readonly("excludes", &mt::Lattice::excludes)
      .def_readonly("same_place", &mt::Lattice::same_place)
      .def_readonly("stats", &mt::Lattice::stats);
  mereo::py_util::register_converter(
      "Lattice", {[](const mereo::graph::Value& v) { return py::cast(v.get<mt::Lattice>()); },
                  [](const py::handle& h) { return mereo::graph::Value::make<mt::Lattice>(h.cast<mt::Lattice>()); }});
  mereo::py_util::register_converter(
      "Segments",
      {[](const mereo::graph::Value& v) { return py::cast(v.get<std::vector<Segment>>()); },
       [](const py::handle& h) { return mereo::graph::Value::make<std::vector<Segment>>(h.cast<std::vector<Segment>>()); }});

  pu::register_options<mt::MatchOptions>("MatchOptions");
  pu::register_options<mt::InterpretOptions>("InterpretOptions");
  // up: against gravity; support_d: the support surface's offset (up.dot(x) + support_d is a
  // point's height above it: the `top`, `bottom` attributes of furniture), NaN for none
  auto options = [](const char* function, const py::kwargs& kw, std::optional<Eigen::Vector3d> up, double support_d) {
    auto o = pu::options_from_kwargs<mt::MatchOptions>(function, kw);
    if (up) o.context.up = *up;
    o.context.support_d = support_d;
    return o;
  };
  m.def("match",
        [options](const kn::Concept& c, const std::vector<Segment>& segs, std::optional<Eigen::Vector3d> up,
                  bool exhaustive, const kn::KnowledgeBase* kb, double support_d, py::kwargs kw) {
          auto o = options("match", kw, up, support_d);
          o.kb = kb;
          mt::MatchStats st;
          std::vector<mt::Hypothesis> h;
          {
            py::gil_scoped_release release;  // Python predicates take it back
            h = exhaustive ? mt::match_exhaustive(c, segs, o, &st) : mt::match(c, segs, o, &st);
          }
          return py::make_tuple(h, st);
        },
        py::arg("concept"), py::arg("segments"), py::arg("up") = py::none(), py::arg("exhaustive") = false,
        py::arg("kb") = nullptr, py::arg("support_d") = std::numeric_limits<double>::quiet_NaN(),
        pu::takes_options(m, "match", "MatchOptions",
                          "The N best hypotheses of a (resolved) concept and the search counters: (list, "
                          "MatchStats). `kb` resolves parts whose class is a concept; `support_d` places the support "
                          "surface (heights above it: up.dot(x) + support_d).")
            .c_str());
  m.def("recognize",
        [options](const kn::KnowledgeBase& kb, const std::vector<std::string>& names, const std::vector<Segment>& segs,
                  std::optional<Eigen::Vector3d> up, double support_d, py::kwargs kw) {
          const auto o = options("recognize", kw, up, support_d);
          py::gil_scoped_release release;
          return mt::recognize(kb, names, segs, o);
        },
        py::arg("kb"), py::arg("concepts"), py::arg("segments"), py::arg("up") = py::none(),
        py::arg("support_d") = std::numeric_limits<double>::quiet_NaN(),
        pu::takes_options(m, "recognize", "MatchOptions",
                          "Every concept matched (in parallel): the lattice of hypotheses; `support_d` places the "
                          "support surface (heights above it: up.dot(x) + support_d).")
            .c_str());
}
