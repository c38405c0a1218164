// models: the graph's object models (knowledge::models_from: the shipped ones, or those of a YAML
// model file with them) and the concepts looked for, loaded and checked once when the graph is
// verified; a constant node (no inputs, runs once per run), the one place of both in a graph.
//
//   nodes:
//     - {name: models, kind: models, options: {models: "mug,jar,can", file: "my_models.yaml"}}
//   edges:
//     - models.models -> objects.models
//     - models.models -> interpretation.models
#include "mereo/knowledge/model_file.hpp"
#include "nodes/node_options.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec models_node() {
  graph::NodeSpec s;
  s.kind = "models";
  s.doc = "The object models (a knowledge base) and the concepts looked for; loaded once per run.";
  s.outputs = {{"models", "ModelSet", "the knowledge base and the concepts looked for"}};
  s.options = options_of<ModelsNodeOptions>();
  s.constant = true;
  s.make = [](const graph::Options& o) {
    // the models are read and checked when the graph is verified, not per frame
    auto opts = options_from<ModelsNodeOptions>(o);
    knowledge::ModelSet m{knowledge::models_from(opts.file), std::move(opts.models)};
    for (const auto& n : m.concepts) m.kb.resolve(n);  // throws InputError naming the unknown concept and the known ones
    const graph::Value value = graph::Value::make(std::move(m));
    return graph::NodeBody([value](graph::NodeContext& ctx) { ctx.set_output("models", value); });
  };
  return s;
}

}  // namespace mereo::nodes
