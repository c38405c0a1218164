// Exact inference in a concept's Bayesian net (see bayes.hpp).
#include "mereo/knowledge/bayes.hpp"

#include <stdexcept>
#include <string>

namespace mereo::knowledge {
namespace {

std::pair<double, double> node_or(const Concept& c, const std::string& key, std::pair<double, double> fallback) {
  const auto it = c.bayes.node.find(key);
  return it == c.bayes.node.end() ? fallback : it->second;
}

/// sum over x in {0, 1} of P(x | C) * L(x), with L = (1 - m, m).
double soft(double p_true, double m) { return p_true * m + (1 - p_true) * (1 - m); }

}  // namespace

std::pair<double, double> present_cpt(const Concept& c, int part) {
  const Part& p = c.parts.at(part);
  return node_or(c, "present:" + p.role, p.optional ? c.bayes.present_optional : c.bayes.present_obligatory);
}
std::pair<double, double> quality_cpt(const Concept& c, int part) {
  return node_or(c, "quality:" + c.parts.at(part).role, c.bayes.quality);
}
std::pair<double, double> satisfied_cpt(const Concept& c, int constraint) {
  return node_or(c, "satisfied:" + std::to_string(constraint), c.bayes.satisfied);
}

double posterior(const Concept& c, const Evidence& e) {
  if (e.state.size() != c.parts.size() || e.quality.size() != c.parts.size() ||
      e.satisfied.size() != c.constraints.size())
    throw std::invalid_argument("posterior: evidence does not fit concept '" + c.name + "'");
  double like[2] = {c.bayes.prior, 1 - c.bayes.prior};  // [C, not C]
  for (std::size_t i = 0; i < c.parts.size(); ++i) {
    if (e.state[i] == PartState::Undecided) continue;  // sums to 1 over presence and quality
    const auto pc = present_cpt(c, int(i));
    const auto qc = quality_cpt(c, int(i));
    for (int k = 0; k < 2; ++k) {
      const double p_present = k == 0 ? pc.first : pc.second;
      if (e.state[i] == PartState::Present)
        like[k] *= p_present * soft(k == 0 ? qc.first : qc.second, e.quality[i]);
      else
        like[k] *= 1 - p_present;
    }
  }
  for (std::size_t j = 0; j < c.constraints.size(); ++j) {
    if (e.satisfied[j] < 0) continue;
    const auto sc = satisfied_cpt(c, int(j));
    like[0] *= soft(sc.first, e.satisfied[j]);
    like[1] *= soft(sc.second, e.satisfied[j]);
  }
  const double z = like[0] + like[1];
  return z > 0 ? like[0] / z : 0.0;
}

}  // namespace mereo::knowledge
