// The ODD as a model: levels and labels of its factors, cells, admissibility; and the rules a
// well-formed ODD obeys (validate). Loading from YAML is in odd_load.cpp.

#include "emrm/scenario/odd.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

#include "emrm/core/text.hpp"
#include "emrm/scenario/plan.hpp"
#include "odd_rules.hpp"

namespace emrm::scenario {

// ---- OddFactor ---------------------------------------------------------------------------------

int OddFactor::levels() const noexcept {
  switch (type) {
    case FactorType::kContinuous:
    case FactorType::kInteger:
      return static_cast<int>(edges.size()) - 1;
    case FactorType::kCategorical:
      return static_cast<int>(classes.size());
    case FactorType::kConstant:
      return 1;
  }
  return 1;
}

int OddFactor::level_of(double value) const noexcept {
  if (is_numeric_range()) {
    // Bin k is [edges[k], edges[k+1]); the last bin is closed.
    const auto it = std::upper_bound(edges.begin(), edges.end(), value);
    const auto k = static_cast<int>(it - edges.begin()) - 1;
    return std::clamp(k, 0, levels() - 1);
  }
  if (type == FactorType::kCategorical) {
    int best = 0;
    for (int k = 1; k < levels(); ++k)
      if (std::abs(class_values[static_cast<std::size_t>(k)] - value) <
          std::abs(class_values[static_cast<std::size_t>(best)] - value))
        best = k;
    return best;
  }
  return 0;
}

std::string OddFactor::level_label(int level) const {
  const auto k = static_cast<std::size_t>(level);
  switch (type) {
    case FactorType::kContinuous:
    case FactorType::kInteger:
      return fmt::format("[{:g}, {:g}{}", edges[k], edges[k + 1], level + 1 == levels() ? "]" : ")");
    case FactorType::kCategorical:
      return classes[k];
    case FactorType::kConstant:
      return fmt::format("{:g}", edges.empty() ? nominal : edges.front());
  }
  return {};
}

double OddFactor::lower(int level) const noexcept {
  const auto k = static_cast<std::size_t>(level);
  if (is_numeric_range()) return edges[k];
  if (type == FactorType::kCategorical) return class_values[k];
  return nominal;
}

double OddFactor::upper(int level) const noexcept {
  const auto k = static_cast<std::size_t>(level);
  if (is_numeric_range()) return edges[k + 1];
  if (type == FactorType::kCategorical) return class_values[k];
  return nominal;
}

double OddFactor::domain_min() const noexcept {
  if (is_numeric_range()) return edges.front();
  if (type == FactorType::kCategorical) return *std::min_element(class_values.begin(), class_values.end());
  return nominal;
}

double OddFactor::domain_max() const noexcept {
  if (is_numeric_range()) return edges.back();
  if (type == FactorType::kCategorical) return *std::max_element(class_values.begin(), class_values.end());
  return nominal;
}

// ---- Odd ---------------------------------------------------------------------------------------

std::vector<std::string> Odd::factor_names() const {
  std::vector<std::string> names;
  names.reserve(factors.size());
  for (const auto& f : factors) names.push_back(f.name);
  return names;
}

std::optional<std::size_t> Odd::factor_index(std::string_view factor_name) const {
  for (std::size_t i = 0; i < factors.size(); ++i)
    if (factors[i].name == factor_name) return i;
  return std::nullopt;
}

std::vector<std::size_t> Odd::influential() const {
  std::vector<std::size_t> q;
  for (std::size_t i = 0; i < factors.size(); ++i)
    if (factors[i].influential && factors[i].levels() > 1) q.push_back(i);
  return q;
}

std::vector<int> Odd::cell_of(std::span<const double> values) const {
  std::vector<int> cell(factors.size());
  for (std::size_t i = 0; i < factors.size(); ++i) cell[i] = factors[i].level_of(values[i]);
  return cell;
}

bool Odd::admissible(std::span<const double> values) const {
  if (relevance && !relevance->holds(values)) return false;
  return std::all_of(constraints.begin(), constraints.end(), [&](const auto& c) { return c.holds(values); });
}

double Odd::cell_count() const noexcept {
  double n = 1.0;
  for (const auto& f : factors) n *= f.levels();
  return n;
}

// ---- the rules ---------------------------------------------------------------------------------

namespace detail {
namespace {

bool valid_identifier(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// A predicate evaluates its values in the order of the names it was compiled with.
void check_compiled_over(core::Validator& v, const core::Expression& e, const std::vector<std::string>& names,
                         std::string_view field) {
  if (e.variables() != names)
    v.fail(field, fmt::format("'{}' is compiled over the factors ({}), not over the ODD's ({})", e.text(),
                              core::join(e.variables(), ", "), core::join(names, ", ")));
}

}  // namespace

void check_factor_domain(core::Validator& v, const OddFactor& f) {
  if (!valid_identifier(f.name))
    v.fail("name", fmt::format("factor name '{}' is not an identifier (letters, digits and _, starting with a letter)",
                               f.name));
  switch (f.type) {
    case FactorType::kContinuous:
    case FactorType::kInteger: {
      if (f.edges.size() < 2)
        v.fail("bins", fmt::format("'bins' needs at least two edges (one bin), got {}", f.edges.size()));
      for (std::size_t k = 1; k < f.edges.size(); ++k)
        if (!(f.edges[k] > f.edges[k - 1]))
          v.fail("bins", fmt::format("bin edges must increase strictly, but {:g} follows {:g} (position {}); bins "
                                     "may not overlap or be unsorted",
                                     f.edges[k], f.edges[k - 1], k + 1));
      if (f.type == FactorType::kInteger)
        for (double e : f.edges)
          if (e != std::round(e))
            v.fail("bins", fmt::format("bin edges of an integer factor must be integers, got {:g}", e));
      for (double k : f.kinks)
        if (!(k > f.edges.front() && k < f.edges.back()))
          v.fail("kinks", fmt::format("kink {:g} lies outside the open domain ({:g}, {:g})", k, f.edges.front(),
                                      f.edges.back()));
      break;
    }
    case FactorType::kCategorical: {
      if (f.classes.empty()) v.fail({}, "a categorical factor needs 'classes': a list of names");
      std::set<std::string> seen;
      for (const auto& c : f.classes)
        if (!seen.insert(c).second) v.fail("classes", fmt::format("duplicate class '{}'", c));
      if (f.class_values.size() != f.classes.size())
        v.fail("values",
               fmt::format("'values' has {} numbers for {} classes", f.class_values.size(), f.classes.size()));
      const std::set<double> distinct(f.class_values.begin(), f.class_values.end());
      if (distinct.size() != f.class_values.size()) v.fail("values", "the classes' values must differ");
      break;
    }
    case FactorType::kConstant:
      break;
  }
}

void check_factor_prior(core::Validator& v, const OddFactor& f) {
  if (static_cast<int>(f.prior.size()) != f.levels())
    v.fail("prior", fmt::format("'prior' has {} probabilities for {} levels", f.prior.size(), f.levels()));
  double sum = 0.0;
  for (double p : f.prior) {
    if (p < 0.0) v.fail("prior", fmt::format("prior probabilities must be >= 0, got {:g}", p));
    sum += p;
  }
  if (std::abs(sum - 1.0) > 1e-6)
    v.fail("prior", fmt::format("prior does not normalise: its probabilities sum to {:.9g}, expected 1", sum));
}

void check_factor_nominal(core::Validator& v, const OddFactor& f) {
  if (f.type == FactorType::kCategorical) {
    if (std::find(f.class_values.begin(), f.class_values.end(), f.nominal) == f.class_values.end())
      v.fail("nominal", fmt::format("nominal {:g} is not the number of a class of '{}' ({})", f.nominal, f.name,
                                    core::join(f.classes, ", ")));
    return;
  }
  if (f.type == FactorType::kInteger && f.nominal != std::round(f.nominal))
    v.fail("nominal",
           fmt::format("nominal of the integer factor '{}' must be a whole number, got {:g}", f.name, f.nominal));
  if (f.nominal < f.domain_min() || f.nominal > f.domain_max())
    v.fail("nominal",
           fmt::format("nominal {:g} lies outside the domain [{:g}, {:g}]", f.nominal, f.domain_min(), f.domain_max()));
}

void check_factor_unique(core::Validator& v, const Odd& odd, std::size_t i) {
  for (std::size_t j = 0; j < i; ++j)
    if (odd.factors[j].name == odd.factors[i].name)
      v.fail("name", fmt::format("duplicate factor '{}'", odd.factors[i].name));
}

void check_factor_count(core::Validator& v, const Odd& odd) {
  if (odd.factors.empty()) v.fail("factors", "an ODD needs at least one factor");
}

std::string budget_message(long long budget) { return fmt::format("budget must be >= 1, got {}", budget); }

void check_coverage(core::Validator& v, const Odd& odd) {
  const core::Validator::Scope coverage(v, "coverage");
  if (odd.strength != 2 && odd.strength != 3)
    v.fail("strength", fmt::format("strength must be 2 or 3, got {}", odd.strength));
  const auto q = odd.influential();
  if (static_cast<std::size_t>(odd.strength) > q.size()) {
    std::vector<std::string> names;
    for (auto i : q) names.push_back(odd.factors[i].name);
    v.fail("strength", fmt::format("strength {} is larger than the number of influential factors with more than one "
                                   "level ({}: {})",
                                   odd.strength, q.size(), names.empty() ? "none" : core::join(names, ", ")));
  }
  if (odd.n_c < 1) v.fail("n_c", fmt::format("n_c must be >= 1, got {}", odd.n_c));
  if (odd.n_m < 0) v.fail("n_m", fmt::format("n_m must be >= 0, got {}", odd.n_m));
  if (!(odd.epsilon > 0.0 && odd.epsilon < 0.5))
    v.fail("epsilon", fmt::format("epsilon must lie in (0, 0.5), got {:g}", odd.epsilon));
  if (!(odd.delta > 0.0 && odd.delta < 1.0))
    v.fail("delta", fmt::format("delta must lie in (0, 1), got {:g}", odd.delta));
  if (odd.budget < 1) v.fail("budget", budget_message(static_cast<long long>(odd.budget)));
}

void check_malfunction(core::Validator& v, const Odd& odd, std::size_t k) {
  const Malfunction& m = odd.malfunctions[k];
  for (std::size_t j = 0; j < k; ++j)
    if (odd.malfunctions[j].id == m.id) v.fail("id", fmt::format("duplicate malfunction mode '{}'", m.id));
  if (m.region) check_compiled_over(v, *m.region, odd.factor_names(), "region");
}

void check_domain_size(core::Validator& v, const Odd& odd) {
  if (odd.cell_count() > 200000)
    v.fail("factors",
           fmt::format("the factors' levels make {:.0f} cells, more than 200000; use fewer bins", odd.cell_count()));
}

void check_satisfiable(core::Validator& v, const Odd& odd) {
  if (!relevant_cells(odd).empty()) return;
  // The relevance predicate, then the constraints one by one: the first whose addition leaves no
  // relevant cell is the culprit.
  Odd partial = odd;
  partial.constraints.clear();
  if (relevant_cells(partial).empty()) v.fail("relevance", "no point of the domain satisfies the relevance predicate");
  const core::Validator::Scope constraints(v, "constraints");
  for (std::size_t i = 0; i < odd.constraints.size(); ++i) {
    partial.constraints.push_back(odd.constraints[i]);
    if (relevant_cells(partial).empty()) {
      const core::Validator::Scope at(v, i);
      v.fail({},
             "the constraints are unsatisfiable: with this one, no point of the domain satisfies the relevance "
             "predicate and every constraint");
    }
  }
}

}  // namespace detail

namespace detail {

void check_odd(core::Validator& v, const Odd& odd) {
  const std::vector<std::string> names = odd.factor_names();
  {
    const core::Validator::Scope factors(v, "factors");
    for (std::size_t i = 0; i < odd.factors.size(); ++i) {
      const core::Validator::Scope at(v, i);
      check_factor_domain(v, odd.factors[i]);
      check_factor_prior(v, odd.factors[i]);
      check_factor_nominal(v, odd.factors[i]);
      check_factor_unique(v, odd, i);
    }
  }
  check_factor_count(v, odd);
  if (odd.relevance) check_compiled_over(v, *odd.relevance, names, "relevance");
  {
    const core::Validator::Scope constraints(v, "constraints");
    for (std::size_t i = 0; i < odd.constraints.size(); ++i) {
      const core::Validator::Scope at(v, i);
      check_compiled_over(v, odd.constraints[i], names, {});
    }
  }
  if (odd.tracked) check_compiled_over(v, *odd.tracked, names, "tracked");
  check_coverage(v, odd);
  {
    const core::Validator::Scope malfunctions(v, "malfunctions");
    for (std::size_t k = 0; k < odd.malfunctions.size(); ++k) {
      const core::Validator::Scope at(v, k);
      check_malfunction(v, odd, k);
    }
  }
  check_domain_size(v, odd);
}

std::vector<RelevantCell> validated_relevant_cells(const Odd& odd) {
  core::Validator v("odd");
  check_odd(v, odd);
  std::vector<RelevantCell> cells = relevant_cells(odd);
  if (cells.empty()) check_satisfiable(v, odd);
  return cells;
}

}  // namespace detail

void validate(const Odd& odd) {
  core::Validator v("odd");
  detail::check_odd(v, odd);
  detail::check_satisfiable(v, odd);
}

}  // namespace emrm::scenario
