// The knowledge base: fuzzy memberships, built-in predicates on analytic shapes, model files and
// their errors, specialization, and the Bayesian judgement against brute-force enumeration.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "mereo/core/error.hpp"
#include "mereo/knowledge/bayes.hpp"
#include "mereo/knowledge/model.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "mereo/knowledge/predicates.hpp"

using namespace mereo;
using namespace mereo::knowledge;

namespace {

const std::string kModels = std::string(MEREO_SOURCE_DIR) + "/graphs/models/tabletop.yaml";

Segment cylinder(Eigen::Vector3d p, Eigen::Vector3d axis, double r, double h) {
  Segment s;
  s.shape = shapes::Cylinder{};
  s.as<shapes::Cylinder>().point = p, s.as<shapes::Cylinder>().axis = axis.normalized(), s.as<shapes::Cylinder>().radius = r, s.as<shapes::Cylinder>().height = h;
  return s;
}
Segment torus(Eigen::Vector3d c, Eigen::Vector3d n, double R, double r) {
  Segment s;
  s.shape = shapes::Torus{};
  s.as<shapes::Torus>().center = c, s.as<shapes::Torus>().normal = n.normalized(), s.as<shapes::Torus>().major_radius = R, s.as<shapes::Torus>().minor_radius = r;
  return s;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(Fuzzy, Trapezoid) {
  const auto m = Membership::range(1.0, 2.0, 0.5);
  EXPECT_DOUBLE_EQ(m(0.4), 0.0);
  EXPECT_DOUBLE_EQ(m(0.75), 0.5);
  EXPECT_DOUBLE_EQ(m(1.5), 1.0);
  EXPECT_DOUBLE_EQ(m(2.25), 0.5);
  EXPECT_DOUBLE_EQ(m(3.0), 0.0);
  EXPECT_DOUBLE_EQ(m(NAN), 0.0);
  EXPECT_DOUBLE_EQ(Membership::range(1, 2)(2.0), 1.0);  // crisp edges
  EXPECT_DOUBLE_EQ(Membership::range(1, 2)(2.0001), 0.0);
  EXPECT_DOUBLE_EQ(Membership::at_most(1, 2)(-1e9), 1.0);
  EXPECT_DOUBLE_EQ(Membership::at_least(1, 2)(1.5), 0.5);
  EXPECT_TRUE(Membership::range(1, 2).within(Membership::range(0, 3)));
  EXPECT_FALSE(Membership::range(0, 3).within(Membership::range(1, 2)));
}

TEST(Predicates, HandleOnBodyAndItsLookalikes) {
  // a mug body (camera-like frame, up = -y) and a handle on its outer wall
  const Eigen::Vector3d up(0, -1, 0);
  Context ctx;
  ctx.up = up;
  const Segment body = cylinder({0, 0, 1}, up, 0.04, 0.1);
  const double R = 0.025, k = 0.6;  // handle ring radius; its centre at r_body + k R from the axis
  const Segment handle = torus({0.04 + k * R, 0, 1}, {0, 0, 1}, R, 0.006);
  Constraint near{"near", {"handle", "body"}, {{"max", 0.01}}, {}, {}};
  Constraint inter{"intersects", {"handle", "body"}, {{"tolerance", 0.004}}, {}, {}};
  Constraint perp{"perpendicular", {"handle", "body"}, {}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(near, {&handle, &body}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(inter, {&handle, &body}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(inter, {&body, &handle}, ctx), 1.0);  // either order
  EXPECT_DOUBLE_EQ(evaluate(perp, {&handle, &body}, ctx), 1.0);
  // a ring standing 2 cm beside the body (a distractor): not attached
  const Segment apart = torus({0.04 + 0.02 + 0.006 + R, 0, 1}, {0, 0, 1}, R, 0.006);
  EXPECT_DOUBLE_EQ(evaluate(inter, {&apart, &body}, ctx), 0.0);
  EXPECT_LT(evaluate(near, {&apart, &body}, ctx), 1.0);
  // a ring above the body's top: not within its height
  const Segment high = torus({0.04 + k * R, -0.1, 1}, {0, 0, 1}, R, 0.006);
  EXPECT_DOUBLE_EQ(evaluate(inter, {&high, &body}, ctx), 0.0);
  // inset: the ring's centre at mid-height passes; 4 mm under the top end it is within the
  // height but not 12 mm inside it (a ring fitted to a tapered cup's rim)
  Constraint inset{"intersects", {"handle", "body"}, {{"tolerance", 0.004}, {"inset", 0.012}}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(inset, {&handle, &body}, ctx), 1.0);
  const Segment rim = torus({0.04 + k * R, -0.046, 1}, {0, 0, 1}, R, 0.006);
  EXPECT_DOUBLE_EQ(evaluate(inter, {&rim, &body}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(inset, {&rim, &body}, ctx), 0.0);
  // the body's upper 4 cm seen (its foot hidden by something in front): the handle lies below the
  // seen part's lower end; with the support under the body its lower end is taken there
  const Segment upper = cylinder({0, -0.03, 1}, up, 0.04, 0.04);
  EXPECT_DOUBLE_EQ(evaluate(inset, {&handle, &upper}, ctx), 0.0);
  Context on_table = ctx;
  on_table.support_d = 0.05;  // the table at y = 0.05, the whole body's foot
  EXPECT_DOUBLE_EQ(evaluate(inset, {&handle, &upper}, on_table), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(inset, {&rim, &body}, on_table), 0.0);  // the upper end stays
  // protrudes: the handle's outer edge 4 cm past the wall; a ring hugging the wall (fitted to a
  // tapered cup's flaring side) 5 mm past it; 17 mm is halfway up the ramp from 16 to 18 mm
  Constraint out{"protrudes", {"handle", "body"}, {{"min", 0.018}, {"margin", 0.002}}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(out, {&handle, &body}, ctx), 1.0);
  const Segment hugging = torus({0.025, 0, 1}, {0, 0, 1}, 0.02, 0.006);
  EXPECT_DOUBLE_EQ(evaluate(out, {&hugging, &body}, ctx), 0.0);
  const Segment halfway = torus({0.037, 0, 1}, {0, 0, 1}, 0.02, 0.006);
  EXPECT_NEAR(evaluate(out, {&halfway, &body}, ctx), 0.5, 1e-9);
  // ring plane not containing the axis direction
  const Segment flat = torus({0.04 + k * R, 0, 1}, up, R, 0.006);
  EXPECT_DOUBLE_EQ(evaluate(perp, {&flat, &body}, ctx), 0.0);
  // a ring turned about the body's axis: perpendicular to it still, but not in a plane through
  // it (a rim's or a neighbour's wall fitted as a ring); a ring centred on the axis has no such plane
  Constraint rad{"radial", {"handle", "body"}, {{"tolerance_deg", 15.0}}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(rad, {&handle, &body}, ctx), 1.0);
  const double turn = 40 * M_PI / 180;
  const Segment turned = torus({0.04 + k * R, 0, 1}, {std::sin(turn), 0, std::cos(turn)}, R, 0.006);
  EXPECT_DOUBLE_EQ(evaluate(perp, {&turned, &body}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(rad, {&turned, &body}, ctx), 0.0);
  const double slight = 20 * M_PI / 180;  // between tolerance and twice it: partly
  const Segment leaning = torus({0.04 + k * R, 0, 1}, {std::sin(slight), 0, std::cos(slight)}, R, 0.006);
  EXPECT_NEAR(evaluate(rad, {&leaning, &body}, ctx), 2.0 / 3.0, 1e-9);
  const Segment about_axis = torus({0, -0.02, 1}, {0, 0, 1}, R, 0.006);
  EXPECT_DOUBLE_EQ(evaluate(rad, {&about_axis, &body}, ctx), 0.0);
  // coaxial, above, same size, distance
  const Segment neck = cylinder({0, -0.12, 1}, up, 0.012, 0.05);
  Constraint coax{"coaxial", {"body", "neck"}, {}, {}, {}};
  Constraint abv{"above", {"neck", "body"}, {}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(coax, {&body, &neck}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(abv, {&neck, &body}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(abv, {&body, &neck}, ctx), 0.0);
  Constraint same{"same_size", {"a", "b"}, {}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(same, {&body, &body}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(same, {&body, &neck}, ctx), 0.0);
  Constraint dist{"distance", {"a", "b"}, {{"min", 0.1}, {"max", 0.2}}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(dist, {&body, &neck}, ctx), 1.0);
  // attributes
  EXPECT_NEAR(attribute_value(body, "tilt_deg", ctx), 0.0, 1e-9);
  EXPECT_NEAR(attribute_value(body, "aspect", ctx), 1.25, 1e-12);
  EXPECT_NEAR(surface_distance(body, {0.1, 0, 1}), 0.06, 1e-12);
  EXPECT_NEAR(surface_distance(handle, handle.origin() + Eigen::Vector3d(R, 0, 0)), 0.0, 1e-12);
}

// stacked_px: a cylinder's base arc under its rim in the image (y down), and what is not one
TEST(Predicates, ABaseArcUnderItsRim) {
  auto arc = [](Eigen::Vector2d c, double a, double b, double angle, double from, double to) {
    Segment s;
    shapes::Arc e;
    e.center_px = c, e.axes_px = {a, b}, e.angle_deg = angle, e.start_deg = from, e.end_deg = to;
    s.shape = e;
    return s;
  };
  const Context ctx;
  const Constraint stacked{"stacked_px", {"rim", "base"}, {{"tolerance_deg", 10.0}, {"min", 8.0}, {"max", 4.0}}, {}, {}};
  auto judge = [&](const Segment& a, const Segment& b) { return evaluate(stacked, {&a, &b}, ctx); };
  const Segment rim = arc({300, 200}, 40, 15, 0, 0, 360);
  // the base 60 px below, its near half hidden: seen from 0 to 180 degrees (y grows: below)
  EXPECT_DOUBLE_EQ(judge(rim, arc({300, 260}, 38, 14, 0, 0, 180)), 1.0);
  // the same ellipse seen on the side towards the rim: no base (an arc of something in front)
  EXPECT_DOUBLE_EQ(judge(rim, arc({300, 260}, 38, 14, 0, 180, 360)), 0.0);
  // off the rim's minor axis by 20 px (half its major semi-axis), turned by 30 degrees, half its
  // size, too near (a rim's inner edge) or too far (a neighbour's arc 6 semi-axes away): none
  EXPECT_DOUBLE_EQ(judge(rim, arc({320, 260}, 38, 14, 0, 0, 180)), 0.0);
  EXPECT_DOUBLE_EQ(judge(rim, arc({300, 260}, 38, 14, 30, 0, 180)), 0.0);
  EXPECT_DOUBLE_EQ(judge(rim, arc({300, 260}, 20, 8, 0, 0, 180)), 0.0);
  EXPECT_DOUBLE_EQ(judge(rim, arc({300, 203}, 37, 13, 0, 0, 180)), 0.0);
  EXPECT_DOUBLE_EQ(judge(rim, arc({300, 440}, 38, 14, 0, 0, 180)), 0.0);
  // a flat edge inside the opening, 8 px down, its seen middle within the rim's ellipse: none
  EXPECT_DOUBLE_EQ(judge(rim, arc({300, 208}, 34, 6, 0, 0, 180)), 0.0);
  EXPECT_DOUBLE_EQ(judge(rim, arc({300, 208}, 34, 9, 0, 0, 180)), 1.0);  // 2 px below the rim: outside
  // a rim seen from above (round) holds no direction: a base below it at any angle counts
  const Segment round = arc({300, 200}, 40, 37, 70, 0, 360);
  EXPECT_DOUBLE_EQ(judge(round, arc({300, 230}, 39, 33, 0, 0, 180)), 1.0);
  // lines and 3-D shapes are no arcs
  EXPECT_DOUBLE_EQ(judge(rim, cylinder({0, 0, 1}, {0, -1, 0}, 0.04, 0.1)), 0.0);
}

// A patch whose upper edge is hidden (cut by the image or an occluder) may reach higher than seen:
// its `top` scores as the best value at or above the one seen; its lower edge likewise. A door
// 1.7 m high as seen, in a range of 1.85-2.4 m: a full member when its top is hidden, not when seen.
TEST(Predicates, HiddenEdgesOfAPatchAreLowerAndUpperBounds) {
  Context ctx;
  ctx.up = -Eigen::Vector3d::UnitY();
  ctx.support_d = 1.5;  // the floor is the plane y = 1.5 (the camera 1.5 m above it)
  shapes::Patch p;
  p.point = Eigen::Vector3d(0, 1.5 - 0.95, 4), p.normal = -Eigen::Vector3d::UnitZ(), p.u_axis = Eigen::Vector3d::UnitX();
  p.size_u = 0.8, p.size_v = 1.5;  // from 0.2 to 1.7 m above the floor
  Attribute top{"leaf", "top", Membership::range(1.85, 2.4, 0.15), ""};
  Attribute bottom{"leaf", "bottom", Membership::at_most(0.05, 0.15), ""};
  const Segment seen{p};
  EXPECT_NEAR(attribute_value(seen, "top", ctx), 1.7, 1e-12);
  EXPECT_NEAR(attribute_value(seen, "bottom", ctx), 0.2, 1e-12);
  EXPECT_NEAR(attribute_value(seen, "span_up", ctx), 1.5, 1e-12);  // its height seen, not its longer side
  EXPECT_DOUBLE_EQ(attribute_membership(seen, top, ctx), 0.0);
  EXPECT_DOUBLE_EQ(attribute_membership(seen, bottom, ctx), 0.0);
  p.top_hidden = p.bottom_hidden = true;
  const Segment hidden{p};
  EXPECT_DOUBLE_EQ(attribute_membership(hidden, top, ctx), 1.0);
  EXPECT_DOUBLE_EQ(attribute_membership(hidden, bottom, ctx), 1.0);
  // a bound never helps a value beyond the range's far side: a top seen at 2.6 m stays out
  p.size_v = 3.3;  // from -0.7 to 2.6 m
  const Segment tall{p};
  EXPECT_DOUBLE_EQ(attribute_membership(tall, top, ctx), 0.0);
  // other classes and attributes: the range as it is
  Attribute width{"leaf", "width", Membership::range(0.65, 1.1, 0.12), ""};
  EXPECT_DOUBLE_EQ(attribute_membership(hidden, width, ctx), 1.0);
}

// convex: two faces of a box (a cabinet's front and top, front and side) meet at a convex edge,
// each one's centre behind the other's plane; a door leaf standing ajar out of its wall meets the
// wall at a concave one, and two faces side by side in one plane are neither.
TEST(Predicates, ConvexIsTwoFacesOfABox) {
  const auto patch = [](Eigen::Vector3d c, Eigen::Vector3d n, Eigen::Vector3d u, double su, double sv) {
    shapes::Patch p;
    p.point = c, p.normal = n, p.u_axis = u, p.size_u = su, p.size_v = sv;
    return Segment{p};
  };
  Context ctx;
  ctx.up = -Eigen::Vector3d::UnitY();
  // the camera at the origin looking along +z; a box 0.6 wide (x from 0.7 to 1.3), 0.4 deep, its
  // front at z = 3 and its top 0.5 m below the eye; the patches' normals face the camera
  const Segment front = patch({1, 0.9, 3}, -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), 0.6, 0.8);
  const Segment top = patch({1, 0.5, 3.2}, -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.6, 0.4);
  const Segment side = patch({0.7, 0.9, 3.2}, -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(), 0.4, 0.8);
  Constraint convex{"convex", {"a", "b"}, {{"margin", 0.05}}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(convex, {&front, &top}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(convex, {&side, &front}, ctx), 1.0);
  // a wall at z = 4 and a leaf ajar before it, hinged on it: the leaf's centre is in front
  const Eigen::Vector3d n = Eigen::Vector3d(-1, 0, -1).normalized();
  const Segment wall = patch({0, 0, 4}, -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), 4, 2.5);
  const Segment leaf = patch({1 - 0.3, 0, 4 - 0.3}, n, Eigen::Vector3d(1, 0, -1).normalized(), 0.85, 2);
  EXPECT_DOUBLE_EQ(evaluate(convex, {&leaf, &wall}, ctx), 0.0);
  const Segment beside = patch({1.6, 0.9, 3}, -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), 0.6, 0.8);
  EXPECT_DOUBLE_EQ(evaluate(convex, {&front, &beside}, ctx), 0.0);
}

// under: a leg stands under a seat (its top up to the seat within `reach`, its centre across up
// within [min, max] of the seat's); a camera looking along +z, up = -y, the seat 0.45 m above a
// floor 1.2 m below the eye.
TEST(Predicates, UnderIsALegBelowASeat) {
  Context ctx;
  ctx.up = -Eigen::Vector3d::UnitY();
  shapes::Patch p;
  p.point = {0, 0.75, 3}, p.normal = -Eigen::Vector3d::UnitY(), p.u_axis = Eigen::Vector3d::UnitX(), p.size_u = 0.45,
  p.size_v = 0.42;
  const Segment seat{p};
  // a leg at the seat's corner, 0.1-0.35 m above the floor (the part the legs' scan sees)
  const Segment corner = cylinder({0.2, 1.2 - 0.225, 3.19}, ctx.up, 0.02, 0.25);
  const Segment column = cylinder({0.01, 1.2 - 0.225, 3.0}, ctx.up, 0.025, 0.25);
  Constraint under{"under", {"a", "b"}, {}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(under, {&seat, &corner}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(under, {&seat, &column}, ctx), 1.0);
  // a dining chair's legs towards the corners, an office chair's column at the middle
  Constraint legs{"under", {"a", "b"}, {{"min", 0.13}, {"max", 0.4}}, {}, {}};
  Constraint middle{"under", {"a", "b"}, {{"max", 0.12}}, {}, {}};
  EXPECT_DOUBLE_EQ(evaluate(legs, {&seat, &corner}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(legs, {&seat, &column}, ctx), 0.0);
  EXPECT_DOUBLE_EQ(evaluate(middle, {&seat, &column}, ctx), 1.0);
  EXPECT_DOUBLE_EQ(evaluate(middle, {&seat, &corner}, ctx), 0.0);
  // a leg ending 0.3 m below the seat (a chair's under a table top) is not the top's; one beside
  // the seat is not under it; one that rises through it is not under it either
  const Segment low = cylinder({0.2, 1.2 - 0.1, 3.19}, ctx.up, 0.02, 0.1);
  const Segment beside = cylinder({0.8, 1.2 - 0.225, 3.0}, ctx.up, 0.02, 0.25);
  const Segment through = cylinder({0.2, 1.2 - 0.5, 3.19}, ctx.up, 0.02, 0.8);
  EXPECT_DOUBLE_EQ(evaluate(under, {&seat, &low}, ctx), 0.0);
  EXPECT_DOUBLE_EQ(evaluate(under, {&seat, &beside}, ctx), 0.0);
  EXPECT_DOUBLE_EQ(evaluate(under, {&seat, &through}, ctx), 0.0);
}

// rest_gap: an axial body's lowest point above the support, from the geometry of a finite
// cylinder (its ends' rims) against a table 0.8 m below a camera looking along it (up = -y).
TEST(Predicates, RestGapIsTheLowestPointAboveTheSupport) {
  Context ctx;
  ctx.support_d = 0.8;  // up.dot(x) + 0.8: the table is the plane y = 0.8
  const Eigen::Vector3d up = -Eigen::Vector3d::UnitY(), side = Eigen::Vector3d::UnitX();
  // standing on the table: centre half its height up
  const Segment standing = cylinder({0, 0.8 - 0.05, 1}, up, 0.04, 0.1);
  EXPECT_NEAR(attribute_value(standing, "rest_gap", ctx), 0.0, 1e-12);
  // lying on its side: axis a radius up; a cylinder through a rounded box's top, its axis 2 cm up
  const Segment lying = cylinder({0, 0.8 - 0.033, 1}, side, 0.033, 0.12);
  EXPECT_NEAR(attribute_value(lying, "rest_gap", ctx), 0.0, 1e-12);
  const Segment sunk = cylinder({0, 0.8 - 0.02, 1}, side, 0.067, 0.1);
  EXPECT_NEAR(attribute_value(sunk, "rest_gap", ctx), -0.047, 1e-12);
  // tilted by 30 degrees: half the height times cos 30, the radius times sin 30
  const Eigen::Vector3d tilted = std::cos(M_PI / 6) * up + std::sin(M_PI / 6) * side;
  const Segment leaning = cylinder({0, 0.8 - 0.2, 1}, tilted, 0.04, 0.1);
  EXPECT_NEAR(attribute_value(leaning, "rest_gap", ctx), 0.2 - 0.05 * std::cos(M_PI / 6) - 0.04 * 0.5, 1e-12);
  // no support: nothing to pass through; no radius and height (a torus): no value
  EXPECT_EQ(attribute_value(standing, "rest_gap", Context{}), INFINITY);
  EXPECT_TRUE(std::isnan(attribute_value(torus({0, 0, 1}, side, 0.03, 0.005), "rest_gap", ctx)));
}

TEST(Models, ShippedFileLoadsAndSpecializes) {
  KnowledgeBase kb;
  load_models(kb, kModels);
  for (const char* n : {"container", "mug", "cup", "jar", "can", "bottle", "plate", "bowl"}) EXPECT_TRUE(kb.has(n)) << n;
  const Concept mug = kb.resolve("mug");
  ASSERT_EQ(mug.parts.size(), 4u);
  EXPECT_EQ(mug.parts[0].role, "body");  // inherited from container first
  EXPECT_EQ(mug.parts[1].role, "handle");
  EXPECT_EQ(mug.parts[2].role, "inside");
  EXPECT_TRUE(mug.parts[2].optional);
  // the inside as a cylinder or as a cone: two modalities, each with the body and the handle
  EXPECT_EQ(mug.parts[3].role, "inside_tapered");
  EXPECT_EQ(mug.parts[3].cls, "cone");
  ASSERT_EQ(mug.modalities.size(), 2u);
  for (const auto& m : mug.modalities) {
    EXPECT_EQ(std::count(m.parts.begin(), m.parts.end(), "body"), 1) << m.name;
    EXPECT_EQ(std::count(m.parts.begin(), m.parts.end(), "handle"), 1) << m.name;
  }
  EXPECT_TRUE(kb.is_a("mug", "container"));
  EXPECT_FALSE(kb.is_a("plate", "container"));
  // the lineage a result names (RecognizedObject::is_a): nearest first, none for a root or an unknown name
  EXPECT_EQ(kb.ancestors("mug"), std::vector<std::string>{"container"});
  EXPECT_TRUE(kb.ancestors("container").empty());
  EXPECT_TRUE(kb.ancestors("no_such_concept").empty());
  // the inherited radius range was narrowed, the tilt kept
  int radius = 0, tilt = 0;
  for (const auto& a : mug.attributes) {
    radius += a.part == "body" && a.name == "radius";
    tilt += a.part == "body" && a.name == "tilt_deg";
    if (a.part == "body" && a.name == "radius") EXPECT_DOUBLE_EQ(a.range.b, 0.03);
  }
  EXPECT_EQ(radius, 1);
  EXPECT_EQ(tilt, 1);
  // levels of detail: the bottle's neck is fine detail
  const Concept bottle = kb.resolve("bottle");
  EXPECT_EQ(select(bottle, "", Detail::Coarse).parts.size(), 1u);
  EXPECT_EQ(select(bottle, "", Detail::Coarse).constraints.size(), 0u);
  EXPECT_EQ(select(bottle, "", Detail::Fine).parts.size(), 2u);
}

TEST(Models, MistakesNameTheFileTheLineAndTheField) {
  KnowledgeBase kb;
  const std::string typo = error_of([&] { load_models(kb, std::string(MEREO_SOURCE_DIR) + "/tests/data/model_typo.yaml"); });
  EXPECT_NE(typo.find("model_typo.yaml:9:"), std::string::npos) << typo;
  EXPECT_NE(typo.find("field 'maxx'"), std::string::npos) << typo;
  const std::string cls =
      error_of([&] { load_models(kb, std::string(MEREO_SOURCE_DIR) + "/tests/data/model_unknown_class.yaml"); });
  EXPECT_NE(cls.find("model_unknown_class.yaml:5:"), std::string::npos) << cls;
  EXPECT_NE(cls.find("field 'class'"), std::string::npos) << cls;
  EXPECT_NE(cls.find("'toroid'"), std::string::npos) << cls;
  // a misspelt key of a part, an unknown attribute, widening an inherited range, bad YAML
  const std::string key = error_of([&] {
    parse_models(kb, "concepts:\n  - name: x\n    parts:\n      - {role: a, clas: cylinder}\n", "k.yaml");
  });
  EXPECT_NE(key.find("k.yaml:4:"), std::string::npos) << key;
  EXPECT_NE(key.find("field 'clas'"), std::string::npos) << key;
  const std::string attr = error_of([&] {
    parse_models(kb,
                 "concepts:\n  - name: x\n    parts: [{role: a, class: cylinder}]\n    attributes:\n"
                 "      - {part: a, attribute: radius_m, range: [0, 1]}\n",
                 "a.yaml");
  });
  EXPECT_NE(attr.find("a.yaml:5:"), std::string::npos) << attr;
  EXPECT_NE(attr.find("field 'attribute'"), std::string::npos) << attr;
  load_models(kb, kModels);
  const std::string widen = error_of([&] {
    parse_models(kb,
                 "concepts:\n  - name: big_mug\n    parent: mug\n    attributes:\n"
                 "      - {part: body, attribute: radius, range: [0.03, 0.2]}\n",
                 "w.yaml");
  });
  EXPECT_NE(widen.find("w.yaml:5:"), std::string::npos) << widen;
  EXPECT_NE(widen.find("widens"), std::string::npos) << widen;
  EXPECT_FALSE(kb.has("big_mug"));  // a failed file adds nothing
  const std::string yaml = error_of([&] { parse_models(kb, "concepts: [\n", "y.yaml"); });
  EXPECT_NE(yaml.find("y.yaml:"), std::string::npos) << yaml;
  EXPECT_NE(error_of([&] { load_models(kb, "/no/such/models.yaml"); }).find("/no/such/models.yaml"), std::string::npos);
  // one concept twice in a file (the second silently won); a key that is a list (yaml-cpp's
  // "bad conversion", no file named); a list where a role belongs; Latin-1 text quoted as \xNN
  const std::string twice = error_of([&] {
    parse_models(kb, "concepts:\n  - {name: saucer, parent: plate}\n  - {name: saucer, parent: bowl}\n", "t.yaml");
  });
  EXPECT_NE(twice.find("t.yaml:3:5: concept 'saucer' is defined twice in this file (first at t.yaml:2:5)"),
            std::string::npos) << twice;
  const std::string list_key = error_of([&] { parse_models(kb, "concepts:\n  - name: s\n    [a, b]: 1\n", "l.yaml"); });
  EXPECT_NE(list_key.find("l.yaml:3:5: field '(a key in a concept)': expected a text, got a list"), std::string::npos)
      << list_key;
  const std::string role = error_of([&] {
    parse_models(kb, "concepts:\n  - name: s\n    constraints:\n      - {predicate: near, parts: [[a], b]}\n", "r.yaml");
  });
  EXPECT_NE(role.find("r.yaml:4:35: field 'parts': expected a text, got a list"), std::string::npos) << role;
  const std::string latin = error_of([&] { parse_models(kb, "concepts:\n  - {name: s, descriptio\xe9: x}\n", "n.yaml"); });
  EXPECT_NE(latin.find("field 'descriptio\\xe9': unknown field"), std::string::npos) << latin;
}

// Brute force: sum the joint over every hidden variable (the concept, undecided presences, every
// quality and satisfaction node), with the soft evidence as likelihood factors.
double brute_force_posterior(const Concept& c, const Evidence& e) {
  const int P = int(c.parts.size()), K = int(c.constraints.size());
  std::vector<std::vector<int>> members(K);
  for (int k = 0; k < K; ++k)
    for (const auto& r : c.constraints[k].parts) members[k].push_back(c.part_index(r));
  const int vars = 1 + P + P + K;  // C, present, quality, satisfied
  double num = 0, den = 0;
  for (long mask = 0; mask < (1L << vars); ++mask) {
    auto bit = [&](int i) { return int((mask >> i) & 1); };
    const int C = bit(0);
    double p = C ? c.bayes.prior : 1 - c.bayes.prior;
    bool consistent = true;
    for (int i = 0; i < P; ++i) {
      const int pres = bit(1 + i), q = bit(1 + P + i);
      if (e.state[i] == PartState::Present && !pres) consistent = false;
      if (e.state[i] == PartState::Missing && pres) consistent = false;
      const auto pc = present_cpt(c, i);
      const double pp = C ? pc.first : pc.second;
      p *= pres ? pp : 1 - pp;
      const auto qc = quality_cpt(c, i);
      const double pq = pres ? (C ? qc.first : qc.second) : 0.5;
      p *= q ? pq : 1 - pq;
      if (e.state[i] == PartState::Present) p *= q ? e.quality[i] : 1 - e.quality[i];
    }
    for (int k = 0; k < K; ++k) {
      const int s = bit(1 + 2 * P + k);
      bool all = true;
      for (int i : members[k]) all = all && bit(1 + i);
      const auto sc = satisfied_cpt(c, k);
      const double ps = all ? (C ? sc.first : sc.second) : 0.5;
      p *= s ? ps : 1 - ps;
      if (e.satisfied[k] >= 0) p *= s ? e.satisfied[k] : 1 - e.satisfied[k];
    }
    if (!consistent) continue;
    den += p;
    if (C) num += p;
  }
  return num / den;
}

TEST(Bayes, PosteriorEqualsBruteForceEnumeration) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(0.01, 0.99);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Concept c;
    c.name = "random";
    const int P = 1 + int(rng() % 4), K = int(rng() % 4);
    for (int i = 0; i < P; ++i) {
      Part p;
      p.role = "p" + std::to_string(i);
      p.cls = "cylinder";
      p.optional = rng() % 2;
      c.parts.push_back(p);
    }
    for (int k = 0; k < K && P >= 2; ++k) {
      Constraint con;
      con.predicate = "near";
      const int a = int(rng() % P);
      int b = int(rng() % P);
      if (b == a) b = (a + 1) % P;
      con.parts = {c.parts[a].role, c.parts[b].role};
      c.constraints.push_back(con);
    }
    c.bayes.prior = U(rng);
    c.bayes.present_obligatory = {U(rng), U(rng)};
    c.bayes.present_optional = {U(rng), U(rng)};
    c.bayes.quality = {U(rng), U(rng)};
    c.bayes.satisfied = {U(rng), U(rng)};
    if (rng() % 2) c.bayes.node["quality:p0"] = {U(rng), U(rng)};
    Evidence e;
    for (int i = 0; i < P; ++i) {
      e.state.push_back(PartState(rng() % 3));
      e.quality.push_back(e.state.back() == PartState::Present ? U(rng) : 0.0);
    }
    for (const auto& con : c.constraints) {
      bool all = true;
      for (const auto& r : con.parts) all = all && e.state[c.part_index(r)] == PartState::Present;
      e.satisfied.push_back(all ? U(rng) : -1.0);
    }
    EXPECT_NEAR(posterior(c, e), brute_force_posterior(c, e), 1e-9) << "trial " << trial;
    ++checked;
  }
  EXPECT_EQ(checked, 300);
}
