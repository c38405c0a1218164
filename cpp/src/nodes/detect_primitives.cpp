// detect_primitives: planes, cylinders, spheres and tori of an organized cloud with normals
// (features::detect_primitives), with a targeted torus search next to every cylinder.
//
//   nodes:
//     - {name: primitives, kind: detect_primitives, options: {seed: 0, min_support: 250}}
//   edges:
//     - cloud.cloud -> primitives.cloud
//     - normals.normals -> primitives.normals
//     - table.roi -> primitives.roi          # optional: only the points above the table
//     - source.frame -> primitives.frame     # optional: colour for the segments' hue, and the
//                                            # unfiltered depth that cylinders and spheres are
//                                            # measured on (when the cloud's depth is filtered)
#include <sstream>

#include "mereo/core/error.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/features/primitives.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec detect_primitives_node() {
  using graph::OptionType;
  const features::DetectOptions def;
  graph::NodeSpec s;
  s.kind = "detect_primitives";
  s.doc = "RANSAC planes, cylinders, spheres and tori (Schnabel et al. 2007, on the image grid), largest first.";
  s.inputs = {{"cloud", "Cloud", "organized XYZ cloud"},
              {"normals", "NormalMap", "per-pixel normals"},
              {"roi", "Mask", "only these pixels (e.g. above the table)", false},
              {"frame", "Frame", "the unfiltered frame: the segments' colour; cylinders and spheres measured on its depth", false}};
  s.outputs = {{"segments", "Segments", "the primitives with parameters and inlier pixels"}};
  s.options = {
      {"seed", OptionType::Int, 0LL, 0, 1e15, {}, "the only source of randomness"},
      {"classes", OptionType::String, std::string("plane,cylinder,sphere,torus"), 0, 0, {}, "classes to look for"},
      {"epsilon", OptionType::Double, def.epsilon, 1e-4, 0.1, {}, "inlier distance at 1 m, metres"},
      {"normal_deviation_deg", OptionType::Double, def.normal_deviation_deg, 1, 90, {}, "inlier normal deviation"},
      {"min_support", OptionType::Int, (long long)def.min_support, 10, 1e7, {}, "fewest pixels of a segment"},
      {"min_support_torus", OptionType::Int, (long long)def.min_support_torus, 10, 1e7, {}, "fewest pixels of a torus"},
      {"max_primitives", OptionType::Int, (long long)def.max_primitives, 1, 10000, {}, "at most this many segments"},
      {"handles_near_cylinders", OptionType::Bool, def.handles_near_cylinders, 0, 0, {},
       "look for a torus next to every cylinder"},
      {"handle_body_min_radius", OptionType::Double, def.handle_body_min_radius, 0, 1, {},
       "... whose radius is at least this, metres"},
      {"handle_body_max_radius", OptionType::Double, def.handle_body_max_radius, 0, 1, {},
       "... and at most this"},
      {"fit_along_rays", OptionType::Bool, def.fit_along_rays, 0, 0, {},
       "fit cylinders and spheres along the rays (depth noise along them); false: by geometric distance"},
      {"max_handle_turn_deg", OptionType::Double, def.max_handle_turn_deg, 0, 90, {},
       "a ring that fits better turned more than this from its body's axis is not a handle (90: no check)"},
  };
  s.make = [](const graph::Options& o) {
    features::DetectOptions d;
    d.seed = std::uint64_t(o.get_int("seed"));
    d.classes.clear();
    std::stringstream list(o.get_string("classes"));
    for (std::string n; std::getline(list, n, ',');) {
      n.erase(0, n.find_first_not_of(' '));
      n.erase(n.find_last_not_of(' ') + 1);
      try {
        d.classes.push_back(primitive_class(n));
      } catch (const std::invalid_argument& e) {
        throw InputError(std::string("option 'classes': ") + e.what());
      }
    }
    d.epsilon = o.get_double("epsilon");
    d.normal_deviation_deg = o.get_double("normal_deviation_deg");
    d.min_support = int(o.get_int("min_support"));
    d.min_support_torus = int(o.get_int("min_support_torus"));
    d.max_primitives = int(o.get_int("max_primitives"));
    d.handles_near_cylinders = o.get_bool("handles_near_cylinders");
    d.handle_body_min_radius = o.get_double("handle_body_min_radius");
    d.handle_body_max_radius = o.get_double("handle_body_max_radius");
    d.max_handle_turn_deg = o.get_double("max_handle_turn_deg");
    d.fit_along_rays = o.get_bool("fit_along_rays");
    return graph::NodeBody([d](graph::NodeContext& ctx) {
      features::DetectOptions q = d;
      if (ctx.has_input("roi")) q.roi = ctx.input<extension::Mask>("roi");
      const ColorImage* color = nullptr;
      if (ctx.has_input("frame")) {
        const Frame& frame = ctx.input<Frame>("frame");
        color = &frame.color;
        q.unfiltered = extension::back_project(frame);
      }
      ctx.output("segments", features::detect_primitives(ctx.input<Cloud>("cloud"), ctx.input<NormalMap>("normals"), q, color));
    });
  };
  return s;
}

}  // namespace mereo::nodes
