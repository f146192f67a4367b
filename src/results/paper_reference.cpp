#include "emrm/results/paper_reference.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <utility>

#include "emrm/core/text.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::results {
namespace {

[[noreturn]] void fail_at(const SourceLocation& where, const std::string& message) { throw InputError(where, message); }

void check_pct(const SourceLocation& where, std::string_view what, double value) {
  if (value < 0.0 || value > 100.0)
    fail_at(where, fmt::format("{} must be a percentage in [0, 100], got {:g}", what, value));
}

bool known_strategy(std::string_view name) { return sim::registered_strategies().find(name) != nullptr; }

// A column of the by-parameter table: a registered strategy that is not a chooser.
bool column_strategy(std::string_view name) {
  const sim::StrategyTable strategies = sim::registered_strategies();
  const sim::StrategyInfo* info = strategies.info(name);
  return info != nullptr && info->role != sim::StrategyRole::kChooser;
}

std::optional<sim::FactorRole> factor_from_name(std::string_view name) {
  for (const sim::FactorRole f : kBreakdownRoles)
    if (factor_name(f) == name) return f;
  return std::nullopt;
}

void validate(const PaperReference& p, const core::YamlNode& root) {
  const SourceLocation top = root.location();
  if (p.fine_grid.feasible_cells < 0) fail_at(top, "fine_grid.feasible_cells must not be negative");
  for (auto [name, v] : {std::pair{"G", p.fine_grid.regions_pct.g}, std::pair{"Y", p.fine_grid.regions_pct.y},
                         std::pair{"O", p.fine_grid.regions_pct.o}, std::pair{"R", p.fine_grid.regions_pct.r}})
    check_pct(root.at("fine_grid").at("regions_pct").at(name).location(), fmt::format("region {}", name), v);
  if (p.emrm_vs_baseline.cells < 0) fail_at(top, "emrm_vs_baseline.cells must not be negative");
  for (const auto& c : p.emrm_vs_baseline.columns) {
    if (!known_strategy(c.strategy))
      fail_at(c.where, fmt::format("unknown strategy '{}' (expected one of {})", c.strategy,
                                   core::join(sim::strategy_names(), ", ")));
    check_pct(c.where, "collision_avoidance_rate_pct", c.collision_avoidance_rate_pct);
    check_pct(c.where, "mitigability_success_pct", c.mitigability_success_pct);
    if (c.mean_residual_impact_speed_kph < 0.0) fail_at(c.where, "mean_residual_impact_speed_kph must not be negative");
  }
  for (const auto& s : p.by_parameter.strategies)
    if (!column_strategy(s)) fail_at(top, fmt::format("by_parameter.strategies: unknown column strategy '{}'", s));
  for (const auto& row : p.by_parameter.rows) {
    const auto factor = factor_from_name(row.factor);
    if (!factor)
      fail_at(row.where, fmt::format("unknown factor '{}' (expected speed, ttc, friction or passage)", row.factor));
    const auto& allowed = level_names(*factor);
    for (const auto& level : row.levels)
      if (std::find(allowed.begin(), allowed.end(), level) == allowed.end())
        fail_at(row.where, fmt::format("unknown level '{}' of factor {} (expected {})", level, row.factor,
                                       core::join(allowed, ", ")));
    for (const auto& [s, values] : row.values.by_strategy)
      if (!column_strategy(s)) fail_at(row.where, fmt::format("values: unknown column strategy '{}'", s));
    for (const auto& s : p.by_parameter.strategies) {
      const auto* values = row.values.of(s);
      if (values == nullptr) fail_at(row.where, fmt::format("values has no list for the column '{}'", s));
      if (values->size() != row.levels.size())
        fail_at(row.where, fmt::format("values.{} has {} entries for {} levels", s, values->size(), row.levels.size()));
      for (double v : *values) check_pct(row.where, fmt::format("values.{}", s), v);
    }
    if (row.tests.size() != 1 && row.tests.size() != row.levels.size())
      fail_at(row.where, fmt::format("tests has {} entries: give one per level ({}) or one total", row.tests.size(),
                                     row.levels.size()));
    for (int t : row.tests)
      if (t < 0) fail_at(row.where, "tests must not be negative");
  }
}

}  // namespace

const std::vector<double>* PaperLevelValues::of(std::string_view strategy) const {
  const auto it = by_strategy.find(std::string(strategy));
  return it != by_strategy.end() ? &it->second : nullptr;
}

const PaperByParameterRow* PaperReference::by_parameter_row(std::string_view factor) const {
  for (const auto& row : by_parameter.rows)
    if (row.factor == factor) return &row;
  return nullptr;
}

PaperReference parse_paper_reference(const std::string& text, const std::string& file_name) {
  const core::YamlNode root = core::YamlNode::parse(text, file_name);
  if (!root.is_map()) root.fail("expected a mapping with version, fine_grid, emrm_vs_baseline, by_parameter, claims");
  // The version first, so a future file fails on its version and not on a field it added.
  const core::YamlNode version = root.at("version");
  if (version.as_int() != 1)
    version.fail(fmt::format("unsupported paper reference version {}; this emrm reads version 1", version.as_int()));
  PaperReference p;
  core::read_yaml(root, p);
  p.file = file_name;
  validate(p, root);
  return p;
}

PaperReference load_paper_reference(const std::filesystem::path& path) {
  return parse_paper_reference(core::read_input_file(path), path.string());
}

}  // namespace emrm::results
