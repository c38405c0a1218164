// mereo/knowledge/model_file.hpp: object models in YAML files (graphs/models/*.yaml).
//
//   concepts:
//     - name: mug
//       parent: container                 # specialization (optional)
//       description: a cylindrical body with a toroidal handle on its outer wall
//       parts:
//         - {role: body, class: cylinder}
//         - {role: handle, class: torus, optional: true, missing_score: 0.4, detail: fine}
//       attributes:                        # fuzzy ranges: [lo, hi] with a soft margin
//         - {part: body, attribute: radius, range: [0.03, 0.055], margin: 0.005}
//       constraints:
//         - {predicate: near, parts: [handle, body], max: 0.01}
//       modalities:                        # alternative part sets (optional)
//         - {name: surface, parts: [body, handle]}
//       bayes: {prior: 0.3, quality: [0.9, 0.25]}   # overrides of the derived net (optional)
//
// Every mistake (a misspelt field, an unknown class, predicate, attribute or parameter, a part
// that does not exist, a range that widens an inherited one) throws InputError naming the file,
// the line and the field.
#pragma once

#include <string>
#include <vector>

#include "mereo/knowledge/model.hpp"

namespace mereo::knowledge {

/// A knowledge base and the concepts looked for in it: what a graph's `models` node loads once
/// and gives the nodes that match and judge hypotheses.
struct ModelSet {
  KnowledgeBase kb;
  std::vector<std::string> concepts;  ///< in the order given; each one resolves in kb
};

/// The shipped models (graphs/models/*.yaml, compiled in): mug, cup, jar, can, bottle, plate,
/// bowl and their parent `container`.
const KnowledgeBase& builtin_models();

/// The models named by `spec`: a path to a YAML file (ends in .yaml or .yml), or "" for the
/// built-in ones.
KnowledgeBase models_from(const std::string& spec);

/// Adds the concepts of a YAML model file to `kb` and validates them all.
void load_models(KnowledgeBase& kb, const std::string& path);
/// The same for YAML text (`file_name` is used in messages).
void parse_models(KnowledgeBase& kb, const std::string& yaml_text, const std::string& file_name = "<text>");

}  // namespace mereo::knowledge
