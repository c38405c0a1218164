// match_models: the object layer: concepts of the knowledge base matched to the frame's
// segments (matching::recognize), the lattice of hypotheses with mutual-exclusion arcs.
//
//   nodes:
//     - {name: objects, kind: match_models, options: {models: "mug,jar,can", best: 5}}
//   edges:
//     - primitives.segments -> objects.segments
//     - source.frame -> objects.frame      # optional: its pose gives "up"
//     - table.plane -> objects.plane       # optional: the table's normal is "up"
#include <sstream>

#include "mereo/core/error.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "mereo/matching/match.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec match_models_node() {
  using graph::OptionType;
  graph::NodeSpec s;
  s.kind = "match_models";
  s.doc = "Object hypotheses: concepts matched to the segments by branch and bound, with exclusion arcs.";
  s.inputs = {{"segments", "Segments", "the frame's segments (camera frame)"},
              {"frame", "Frame", "the frame; with a pose, 'up' comes from it (else the camera's -y)", false},
              {"plane", "SupportPlane", "the support plane; its normal is 'up' (before the frame's pose)", false}};
  s.outputs = {{"lattice", "Lattice", "hypotheses (best first per concept) and exclusion arcs"}};
  s.options = {
      {"models", OptionType::String, std::string("mug,cup,jar,can,bottle,plate,bowl"), 0, 0, {},
       "comma-separated concepts to look for"},
      {"file", OptionType::String, std::string(""), 0, 0, {}, "a YAML model file (empty: the shipped models)"},
      {"best", OptionType::Int, 10LL, 1, 1000, {}, "hypotheses kept per concept"},
      {"min_score", OptionType::Double, 0.05, 0, 1, {}, "hypotheses below this score are dropped"},
  };
  s.make = [](const graph::Options& o) {
    // the models are read and checked when the graph is built, not per frame
    auto kb = std::make_shared<const knowledge::KnowledgeBase>(knowledge::models_from(o.get_string("file")));
    std::vector<std::string> names;
    std::stringstream list(o.get_string("models"));
    for (std::string n; std::getline(list, n, ',');) {
      n.erase(0, n.find_first_not_of(' '));
      n.erase(n.find_last_not_of(' ') + 1);
      if (n.empty()) continue;
      kb->resolve(n);  // throws InputError naming the unknown concept and the known ones
      names.push_back(n);
    }
    matching::MatchOptions mo;
    mo.best = int(o.get_int("best"));
    mo.min_score = o.get_double("min_score");
    return graph::NodeBody([kb, names, mo](graph::NodeContext& ctx) {
      matching::MatchOptions m = mo;
      if (ctx.has_input("frame")) {
        const Frame& f = ctx.input<Frame>("frame");
        if (f.pose) m.context.up = f.pose->linear().transpose() * Eigen::Vector3d::UnitZ();
      }
      if (ctx.has_input("plane")) {
        const auto& p = ctx.input<extension::SupportPlane>("plane");
        if (p.inlier_count > 0) m.context.up = p.normal;
      }
      ctx.output("lattice", matching::recognize(*kb, names, ctx.input<std::vector<Segment>>("segments"), m));
    });
  };
  return s;
}

}  // namespace mereo::nodes
