// Options described once (mereo/core/options.hpp): the descriptor machinery on a small struct,
// and every built-in node's option list against the description of its options struct.
#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <set>

#include "mereo/cognitive/tracking.hpp"
#include "mereo/core/options.hpp"
#include "mereo/extension/normals.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/features/edges.hpp"
#include "mereo/features/legs.hpp"
#include "mereo/features/primitives.hpp"
#include "mereo/features/patches.hpp"
#include "mereo/features/regions.hpp"
#include "mereo/matching/interpret.hpp"
#include "mereo/signal/depth_filter.hpp"
#include "nodes/node_options.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

using namespace mereo;

namespace {

enum class Shade { Light, Dark };

struct Inner {
  double gain = 2.0;
  int steps = 3;
  static const Fields<Inner>& fields() {
    static const Fields<Inner> f = {field("gain", &Inner::gain, 0, 10, "a gain"),
                                    field("steps", &Inner::steps, 1, 100, "some steps")};
    return f;
  }
};

struct Toy {
  std::uint64_t seed = 7;
  std::size_t count = 5;
  bool on = true;
  std::string name = "toy";
  Shade shade = Shade::Dark;
  std::vector<Shade> shades{Shade::Light, Shade::Dark};
  std::vector<std::string> tags{"a", "b"};
  Inner inner = [] {
    Inner i;
    i.gain = 4.0;  // the outer struct's default wins
    return i;
  }();
  int not_an_option = 42;
  static const Fields<Toy>& fields() {
    static const Fields<Toy> f = concat<Toy>(
        {field("seed", &Toy::seed, 0, 1e15, "a seed"), field("count", &Toy::count, 0, 10, "a count"),
         field("on", &Toy::on, "a switch"), field("name", &Toy::name, "a name"),
         choice("shade", &Toy::shade, {{"light", Shade::Light}, {"dark", Shade::Dark}}, "a shade"),
         list("shades", &Toy::shades,
              [](Shade s) { return s == Shade::Light ? "light" : "dark"; },
              [](const std::string& s) {
                if (s == "light") return Shade::Light;
                if (s == "dark") return Shade::Dark;
                throw std::invalid_argument("no shade '" + s + "'");
              },
              "shades"),
         list("tags", &Toy::tags, "tags")},
        nested(&Toy::inner, Inner::fields(), "inner_"));
    return f;
  }
};

const Field<Toy>& toy_field(const std::string& name) {
  for (const auto& f : Toy::fields())
    if (f.name == name) return f;
  throw std::logic_error("no field " + name);
}

template <typename Fn>
std::string input_error(Fn fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(Options, DefaultsComeFromTheDefaultConstructedStruct) {
  const auto info = describe<Toy>();
  ASSERT_EQ(info.size(), 9u);  // not_an_option is not described
  std::map<std::string, FieldValue> def;
  for (const auto& f : info) def[f.name] = f.default_value;
  EXPECT_EQ(std::get<long long>(def["seed"]), 7);
  EXPECT_EQ(std::get<long long>(def["count"]), 5);
  EXPECT_EQ(std::get<bool>(def["on"]), true);
  EXPECT_EQ(std::get<std::string>(def["name"]), "toy");
  EXPECT_EQ(std::get<std::string>(def["shade"]), "dark");
  EXPECT_EQ(std::get<std::vector<std::string>>(def["shades"]), (std::vector<std::string>{"light", "dark"}));
  EXPECT_EQ(std::get<std::vector<std::string>>(def["tags"]), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(std::get<double>(def["inner_gain"]), 4.0);
  EXPECT_EQ(std::get<long long>(def["inner_steps"]), 3);
  EXPECT_EQ(info[4].kind, FieldKind::Choice);
  EXPECT_EQ(info[4].choices, (std::vector<std::string>{"light", "dark"}));
  EXPECT_EQ(info[7].min, 0);
  EXPECT_EQ(info[7].max, 10);
  EXPECT_EQ(info[7].doc, "a gain");
}

TEST(Options, AssignConvertsAndSetsTheMember) {
  Toy t;
  assign(t, toy_field("seed"), FieldValue(123456789012LL));
  EXPECT_EQ(t.seed, 123456789012ULL);
  assign(t, toy_field("count"), FieldValue(3.0));  // an integral real for an Int
  EXPECT_EQ(t.count, 3u);
  assign(t, toy_field("inner_gain"), FieldValue(1LL));  // an integer for a Real
  EXPECT_EQ(t.inner.gain, 1.0);
  assign(t, toy_field("inner_steps"), FieldValue(9LL));
  EXPECT_EQ(t.inner.steps, 9);
  assign(t, toy_field("on"), FieldValue(false));
  EXPECT_FALSE(t.on);
  assign(t, toy_field("shade"), FieldValue(std::string("light")));
  EXPECT_EQ(t.shade, Shade::Light);
  assign(t, toy_field("shades"), FieldValue(std::string(" dark, light ,,dark")));  // text: split, trimmed
  EXPECT_EQ(t.shades, (std::vector<Shade>{Shade::Dark, Shade::Light, Shade::Dark}));
  assign(t, toy_field("tags"), FieldValue(std::vector<std::string>{"x"}));
  EXPECT_EQ(t.tags, (std::vector<std::string>{"x"}));
  assign(t, toy_field("name"), FieldValue(std::string("other")));
  EXPECT_EQ(t.name, "other");
  EXPECT_EQ(toy_field("inner_gain").get(t), FieldValue(1.0));
}

TEST(Options, AssignRejectsBadValuesNamingTheOption) {
  Toy t;
  EXPECT_NE(input_error([&] { assign(t, toy_field("count"), FieldValue(11LL)); }).find("option 'count': 11 is outside its range [0, 10]"),
            std::string::npos);
  EXPECT_NE(input_error([&] { assign(t, toy_field("count"), FieldValue(2.5)); }).find("option 'count': must be int"),
            std::string::npos);
  EXPECT_NE(input_error([&] { assign(t, toy_field("inner_gain"), FieldValue(-1.0)); }).find("option 'inner_gain'"),
            std::string::npos);
  EXPECT_NE(input_error([&] { assign(t, toy_field("on"), FieldValue(1LL)); }).find("option 'on': must be bool"),
            std::string::npos);
  EXPECT_NE(input_error([&] { assign(t, toy_field("shade"), FieldValue(std::string("grey"))); })
                .find("option 'shade': unknown shade 'grey' (known: light, dark)"),
            std::string::npos);
  EXPECT_NE(input_error([&] { assign(t, toy_field("shades"), FieldValue(std::string("light,grey"))); })
                .find("option 'shades': no shade 'grey'"),
            std::string::npos);
  EXPECT_EQ(t.count, 5u);
  EXPECT_EQ(t.shades, (std::vector<Shade>{Shade::Light, Shade::Dark}));  // unchanged by a failed assign
}

TEST(Options, TextOfValues) {
  EXPECT_EQ(to_text(FieldValue(true)), "true");
  EXPECT_EQ(to_text(FieldValue(0.006)), "0.006");
  EXPECT_EQ(to_text(FieldValue(250LL)), "250");
  EXPECT_EQ(to_text(FieldValue(std::vector<std::string>{"plane", "torus"})), "plane,torus");
  EXPECT_EQ(split_list(""), std::vector<std::string>{});
  EXPECT_EQ(field_names(Inner::fields()), "gain, steps");
}

TEST(Options, NodeOptionsRoundTrip) {
  // the node's option list from the description, and the struct back from the validated values
  graph::NodeSpec s;
  s.kind = "toy";
  s.options = nodes::options_of<Toy>();
  ASSERT_EQ(s.options.size(), 9u);
  EXPECT_EQ(s.options[6].type, graph::OptionType::String);
  EXPECT_EQ(std::get<std::string>(s.options[5].default_value), "light,dark");
  EXPECT_EQ(s.options[4].choices, (std::vector<std::string>{"light", "dark"}));
  const auto given = s.validate("t", {{"seed", 3LL}, {"shades", std::string("dark")}, {"inner_gain", 0.5}});
  const Toy t = nodes::options_from<Toy>(given);
  EXPECT_EQ(t.seed, 3u);
  EXPECT_EQ(t.shades, std::vector<Shade>{Shade::Dark});
  EXPECT_EQ(t.inner.gain, 0.5);
  EXPECT_EQ(t.inner.steps, 3);
  EXPECT_EQ(t.name, "toy");
  EXPECT_NE(input_error([&] { nodes::options_from<Toy>(s.validate("t", {{"shades", std::string("blue")}})); })
                .find("option 'shades'"),
            std::string::npos);
}

namespace {

/// Which node kind takes which options struct: every option of the node is a described field of
/// the struct and the other way round, in the same order, with the same type, default, range,
/// choices and doc.
template <class T>
void expect_node_options_are(const std::vector<graph::NodeSpec>& specs, const std::string& kind) {
  SCOPED_TRACE(kind);
  const graph::NodeSpec* spec = nullptr;
  for (const auto& s : specs)
    if (s.kind == kind) spec = &s;
  ASSERT_TRUE(spec);
  const auto fields = describe<T>();
  ASSERT_EQ(spec->options.size(), fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const auto& o = spec->options[i];
    const auto& f = fields[i];
    SCOPED_TRACE(f.name);
    EXPECT_EQ(o.name, f.name);
    EXPECT_EQ(o.doc, f.doc);
    EXPECT_FALSE(f.doc.empty());
    switch (f.kind) {
      case FieldKind::Bool:
        EXPECT_EQ(o.type, graph::OptionType::Bool);
        EXPECT_EQ(std::get<bool>(o.default_value), std::get<bool>(f.default_value));
        break;
      case FieldKind::Int:
        EXPECT_EQ(o.type, graph::OptionType::Int);
        EXPECT_EQ(std::get<long long>(o.default_value), std::get<long long>(f.default_value));
        break;
      case FieldKind::Real:
        EXPECT_EQ(o.type, graph::OptionType::Double);
        EXPECT_EQ(std::get<double>(o.default_value), std::get<double>(f.default_value));
        break;
      case FieldKind::Text:
      case FieldKind::Choice:
      case FieldKind::List:
        EXPECT_EQ(o.type, graph::OptionType::String);
        EXPECT_EQ(std::get<std::string>(o.default_value), to_text(f.default_value));
        break;
    }
    if (f.kind == FieldKind::Int || f.kind == FieldKind::Real) {
      EXPECT_EQ(o.min, f.min);
      EXPECT_EQ(o.max, f.max);
      EXPECT_LE(f.min, f.max);
      const double def = f.kind == FieldKind::Int ? double(std::get<long long>(f.default_value)) : std::get<double>(f.default_value);
      EXPECT_TRUE(def >= f.min && def <= f.max) << "the default lies outside the range";
    }
    EXPECT_EQ(o.choices, f.choices);
  }
  // the node makes its body from its defaults: the struct is filled without an error
  EXPECT_NO_THROW(nodes::options_from<T>(spec->validate(kind, {})));
}

}  // namespace

TEST(Options, EveryNodeTakesTheOptionsOfItsStruct) {
  const auto specs = nodes::builtin_node_specs();
  expect_node_options_are<features::DetectOptions>(specs, "detect_primitives");
  expect_node_options_are<features::RegionOptions>(specs, "find_regions");
  expect_node_options_are<features::PatchOptions>(specs, "detect_patches");
  expect_node_options_are<features::LegOptions>(specs, "detect_legs");
  expect_node_options_are<features::EdgePrimitiveOptions>(specs, "detect_edges");
  expect_node_options_are<extension::NormalOptions>(specs, "estimate_normals");
  expect_node_options_are<extension::SupportPlaneOptions>(specs, "support_plane");
  expect_node_options_are<signal::DepthFilterOptions>(specs, "filter_depth");
  expect_node_options_are<nodes::ModelsNodeOptions>(specs, "models");
  expect_node_options_are<nodes::MatchModelsNodeOptions>(specs, "match_models");
  expect_node_options_are<matching::InterpretOptions>(specs, "interpret");
  expect_node_options_are<nodes::ReportNodeOptions>(specs, "report");
  expect_node_options_are<cognitive::TrackOptions>(specs, "track_objects");
  expect_node_options_are<nodes::OdometryNodeOptions>(specs, "odometry");
  // and no other kind has options
  const std::set<std::string> checked{"detect_primitives", "estimate_normals", "support_plane", "filter_depth",
                                      "models",            "match_models",     "interpret",     "report",
                                      "track_objects",     "odometry",         "find_regions",  "detect_edges",
                                      "detect_patches",    "detect_legs"};
  for (const auto& s : specs)
    if (!s.options.empty())
      EXPECT_TRUE(checked.count(s.kind)) << "node kind " << s.kind << " has options but no described options struct in this test";
}

TEST(Options, NestedStructsKeepTheirNamesAndTheNodesDefaults) {
  // the node-level structs hold the library structs: same names, the node's own defaults
  const auto match = describe<nodes::MatchModelsNodeOptions>();
  ASSERT_EQ(match.size(), 2u);
  EXPECT_EQ(match[0].name, "best");
  EXPECT_EQ(std::get<long long>(match[0].default_value), matching::MatchOptions{}.best);
  EXPECT_EQ(match[1].name, "min_score");
  EXPECT_EQ(std::get<double>(match[1].default_value), 0.05);  // the node prunes; match() keeps all above 1e-6
  const auto models = describe<nodes::ModelsNodeOptions>();
  ASSERT_EQ(models.size(), 2u);
  EXPECT_EQ(to_text(models[0].default_value), "mug,cup,tapered_cup,pitcher,jar,can,bottle,plate,bowl");
}

TEST(Options, DetectPrimitivesClassesByName) {
  features::DetectOptions d;
  const auto& fields = features::DetectOptions::fields();
  const Field<features::DetectOptions>* classes = nullptr;
  for (const auto& f : fields)
    if (f.name == "classes") classes = &f;
  ASSERT_TRUE(classes);
  assign(d, *classes, FieldValue(std::string("torus, plane")));
  EXPECT_EQ(d.classes, (std::vector<PrimitiveClass>{PrimitiveClass::of<shapes::Torus>(), PrimitiveClass::of<shapes::Plane>()}));
  EXPECT_NE(input_error([&] { assign(d, *classes, FieldValue(std::string("plane,cube"))); }).find("option 'classes'"),
            std::string::npos);
  EXPECT_EQ(to_text(classes->get(features::DetectOptions{})), "plane,cylinder,torus,sphere");
}
