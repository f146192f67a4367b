#include "emrm/workflow/plan_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>

#include "emrm/campaign/campaign.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::workflow {
namespace {

using scenario::FactorType;
using scenario::OddFactor;

// One spelling per unit, so that "kph" and "km/h" agree.
std::string canonical_unit(std::string unit) {
  std::erase_if(unit, [](unsigned char c) { return std::isspace(c); });
  std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return std::tolower(c); });
  if (unit == "kph" || unit == "kmh" || unit == "km/hr") return "km/h";
  if (unit == "sec" || unit == "second" || unit == "seconds") return "s";
  if (unit == "meter" || unit == "meters" || unit == "metre" || unit == "metres") return "m";
  if (unit.empty() || unit == "-" || unit == "none" || unit == "dimensionless") return "1";
  return unit;
}

// The values of a factor's domain as written, in file order: bin edges, class values or the constant.
std::vector<double> written_values(const OddFactor& f) {
  if (f.is_numeric_range()) return f.edges;
  if (f.type == FactorType::kCategorical) return f.class_values;
  return {f.nominal};
}

// Where value `v` of the factor's domain was written (the factor's place when not known).
SourceLocation value_location(const OddFactor& f, double v) {
  const auto values = written_values(f);
  const auto at = static_cast<std::size_t>(std::find(values.begin(), values.end(), v) - values.begin());
  return at < f.value_where.size() ? f.value_where[at] : f.where;
}

std::string located_warning(const SourceLocation& where, const std::string& message) {
  return fmt::format("{}: warning: {}", where.str(), message);
}

// "a friction coefficient in (0, 2]", "an ego speed > 0 km/h".
std::string expected_text(const sim::Factor& l) {
  const std::string article = std::string("aeiou").find(l.what.front()) != std::string::npos ? "an" : "a";
  const std::string unit = l.unit == "1" ? "" : " " + l.unit;
  const sim::FactorLimits& in = l.limits;
  if (std::isinf(in.high))
    return fmt::format("{} {} {} {:g}{}", article, l.what, in.low_inclusive ? ">=" : ">", in.low, unit);
  return fmt::format("{} {} in {}{:g}, {:g}]{}", article, l.what, in.low_inclusive ? "[" : "(", in.low, in.high, unit);
}

// A likely slip behind a rejected value: a percentage for a plain number, a wider road than the scene's.
std::string hint(const sim::Factor& l, double v) {
  const std::string slip = l.slip_hint(v);
  return slip.empty() ? slip : "; " + slip;
}

// A categorical factor of the family: the ODD names its levels as classes, each class's number the
// level's index (the number a cell holds), so that a class is simulated as the level it names.
void check_categorical_factor(const OddFactor& f, const sim::Factor& l) {
  const std::string levels = core::join(l.levels, ", ");
  if (f.type != FactorType::kCategorical && f.type != FactorType::kConstant)
    throw InputError(f.where, fmt::format("{}: a {} factor of {} levels ({}): expected type: categorical with "
                                          "classes: [{}] (or some of them)",
                                          f.name, core::enum_name(f.type), l.levels.size(), levels, levels));
  if (f.type == FactorType::kConstant) return;  // its number is checked against the levels' indices below
  for (std::size_t k = 0; k < f.classes.size(); ++k) {
    const auto at = l.level(f.classes[k]);
    const SourceLocation where = k < f.value_where.size() ? f.value_where[k] : f.where;
    if (!at)
      throw InputError(where, fmt::format("{}: class '{}': expected one of the levels {} of the scene's family", f.name,
                                          f.classes[k], levels));
    if (f.class_values[k] != static_cast<double>(*at))
      throw InputError(where,
                       fmt::format("{}: class '{}' has the number {:g}, but the simulator reads {:g} as '{}'; "
                                   "leave out `values:` and list the classes in the levels' order ({}), or "
                                   "give '{}' the number {}",
                                   f.name, f.classes[k], f.class_values[k], f.class_values[k],
                                   l.accepts(f.class_values[k]) ? l.levels[static_cast<std::size_t>(f.class_values[k])]
                                                                : std::string("no level"),
                                   levels, f.classes[k], *at));
  }
}

void check_factor(const OddFactor& f, const sim::Factor& l) {
  if (l.categorical()) check_categorical_factor(f, l);
  if (!f.unit.empty() && canonical_unit(f.unit) != canonical_unit(l.unit))
    throw InputError(f.unit_where, fmt::format("{}: unit '{}': expected {} (the simulator reads {} as {}); convert "
                                               "the values or rename the factor",
                                               f.name, f.unit, l.unit == "1" ? "a plain number ('1')" : l.unit, f.name,
                                               expected_text(l)));
  for (double v : written_values(f))
    if (!l.accepts(v))
      throw InputError(value_location(f, v),
                       fmt::format("{} {:g}: expected {}{}", f.name, v, expected_text(l), hint(l, v)));
}

// "scene.yaml:80:1" for the scene's max_initial_distance_m, or what stands for it.
std::string distance_limit_place(const scenario::Odd& odd) {
  if (!odd.scene_file) return "the default scene";
  const auto node = core::YamlNode::load_file(*odd.scene_file).find("max_initial_distance_m");
  return node ? node->location().str() : odd.scene_file->string() + ", its default";
}

}  // namespace

std::vector<std::string> family_levels(const std::optional<std::filesystem::path>& scene_file,
                                       const std::string& factor) {
  const sim::SceneConfig scene = scene_file ? sim::load_scene_config(*scene_file) : sim::SceneConfig{};
  const sim::FactorTable factors = sim::scenario_factors(scene);
  const auto i = factors.find(factor);
  return i ? factors[*i].levels : std::vector<std::string>{};
}

sim::SceneConfig plan_scene(const scenario::Odd& odd) {
  return odd.scene_file ? sim::load_scene_config(*odd.scene_file) : sim::SceneConfig{};
}

void check_odd_against_scene(const scenario::Odd& odd, const sim::SceneConfig& scene) {
  const sim::FactorTable factors = sim::scenario_factors(scene);
  for (const auto& f : odd.factors)
    if (const auto i = factors.find(f.name)) check_factor(f, factors[*i]);
  // The strategies `emrm run` will simulate, named at plan time where the ODD names them (an
  // unknown one passed `plan` and failed in `run`, at the generated scenarios.json:1:1).
  const auto check_strategy = [&](const std::string& name, const SourceLocation& where, std::string_view what) {
    if (!sim::known_strategy(name))
      throw InputError(where, fmt::format("{}: {}", what, sim::unknown_strategy_message(name)));
  };
  for (std::size_t k = 0; k < odd.strategies.size(); ++k)
    check_strategy(odd.strategies[k], k < odd.strategies_where.size() ? odd.strategies_where[k] : SourceLocation{},
                   "strategies");
  if (!odd.acceptance_strategy.empty()) check_strategy(odd.acceptance_strategy, odd.acceptance_where, "acceptance");
}

std::vector<std::string> safety_range_warnings(const scenario::Odd& odd, const safety::SafetyCase& sc) {
  std::vector<std::string> warnings;
  for (const auto& sf : sc.factors) {
    const auto i = odd.factor_index(sf.name);
    if (!i) continue;
    const OddFactor& f = odd.factors[*i];
    if (!f.unit.empty() && !sf.unit.empty() && canonical_unit(f.unit) != canonical_unit(sf.unit))
      warnings.push_back(
          located_warning(f.unit_where, fmt::format("{}: unit '{}' in the ODD, '{}' in the safety case ({})", f.name,
                                                    f.unit, sf.unit, sf.where.str())));
    const bool below = sf.min && f.domain_min() < *sf.min;
    const bool above = sf.max && f.domain_max() > *sf.max;
    if (!below && !above) continue;
    const double beyond = above ? f.domain_max() : f.domain_min();
    warnings.push_back(located_warning(
        value_location(f, beyond),
        fmt::format("{} spans [{:g}, {:g}] in the ODD, beyond [{}, {}] of the safety case ({}); its UCA regions and "
                    "ratings were written for that range",
                    f.name, f.domain_min(), f.domain_max(), sf.min ? fmt::format("{:g}", *sf.min) : "-inf",
                    sf.max ? fmt::format("{:g}", *sf.max) : "inf", sf.where.str())));
  }
  return warnings;
}

std::vector<std::string> placement_warnings(const scenario::Odd& odd, const scenario::Plan& plan,
                                            const sim::SceneConfig& scene) {
  std::size_t beyond = 0;
  double farthest_m = 0.0;
  std::size_t other = 0;  // infeasible for a reason of the family's (SceneLayout::infeasible)
  std::string first_reason;
  const sim::FactorTable factors = sim::scenario_factors(scene);
  for (const auto& s : plan.scenarios) {
    sim::CellInput cell = factors.defaults();
    for (std::size_t i = 0; i < odd.factors.size(); ++i) (void)factors.set(cell, odd.factors[i].name, s.values[i]);
    const sim::Scene placed(scene, cell);
    if (placed.feasible()) continue;
    if (!placed.layout().infeasible.empty()) {
      if (other++ == 0) first_reason = placed.layout().infeasible;
      continue;
    }
    ++beyond;
    farthest_m = std::max(farthest_m, placed.initial_distance_m());
  }
  std::vector<std::string> warnings;
  const SourceLocation where = odd.relevance ? odd.relevance->where() : SourceLocation{odd.file, 1, 1};
  if (beyond > 0) {
    const std::string rule = odd.relevance ? fmt::format("the relevance rule '{}' admits them", odd.relevance->text())
                                           : std::string("the ODD has no relevance rule");
    warnings.push_back(located_warning(
        where, fmt::format("{} of {} planned scenarios lie beyond the scene's max_initial_distance_m = {:g} m ({}): "
                           "their initial distance reaches {:.3g} m, so `emrm run` finds them infeasible; {}: make "
                           "it agree with the scene",
                           beyond, plan.scenarios.size(), scene.max_initial_distance_m, distance_limit_place(odd),
                           farthest_m, rule)));
  }
  if (other > 0)
    warnings.push_back(located_warning(
        where, fmt::format("{} of {} planned scenarios cannot be laid out in the scene, so `emrm run` finds them "
                           "infeasible (the first: {}); narrow the ODD or its relevance rule",
                           other, plan.scenarios.size(), first_reason)));
  return warnings;
}

}  // namespace emrm::workflow
