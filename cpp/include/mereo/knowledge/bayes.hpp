// mereo/knowledge/bayes.hpp: the Bayesian judgement of hypotheses (Kasprzak et al.: a net per
// concept, so that partial and complete assignments are scored by the same method).
//
// The net of a concept C (binary: "this is a C"): C is the cause; for every part i a node
// present_i (child of C), a node quality_i (child of C and present_i: the part's data fits its
// attributes), and for every constraint k a node satisfied_k (child of C and the presence of its
// parts). Conditional probabilities come from the model's BayesParams ({P(x | C), P(x | not C)});
// quality and satisfied of absent parts are uninformative (0.5). Evidence from a hypothesis:
// presence observed for assigned parts (true) and for parts decided missing (false), nothing for
// parts not yet decided; quality and satisfaction as soft (virtual) evidence with likelihood
// (m, 1 - m) from the fuzzy membership m. Inference is exact (the evidence factorises given C).
#pragma once

#include <vector>

#include "mereo/knowledge/model.hpp"

namespace mereo::knowledge {

/// The state of one part in a (partial) hypothesis.
enum class PartState { Undecided, Present, Missing };

/// Evidence on a concept's net: per part its state and (if present) the quality membership in
/// [0, 1]; per constraint its value in [0, 1], or a negative number when not all its parts are
/// present (no evidence).
struct Evidence {
  std::vector<PartState> state;
  std::vector<double> quality;
  std::vector<double> satisfied;
};

/// The conditional probabilities of one node, {P(x = 1 | C), P(x = 1 | not C)}.
std::pair<double, double> present_cpt(const Concept& c, int part);
std::pair<double, double> quality_cpt(const Concept& c, int part);
std::pair<double, double> satisfied_cpt(const Concept& c, int constraint);

/// P(C | evidence), exact.
double posterior(const Concept& c, const Evidence& e);

}  // namespace mereo::knowledge
