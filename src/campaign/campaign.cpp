#include "emrm/campaign/campaign.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "emrm/core/domain.hpp"
#include "emrm/core/text.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/version.hpp"

namespace emrm::campaign {
namespace {

using core::scalar_number;

/// "A, B, C or D": the scenario's factors' keys, for messages.
// The fields a campaign and a grid take besides a grid's factors: what an unknown one is told.
const std::vector<std::string> kCampaignFields{"scene", "seed", "strategies", "max_cells",
                                               "grids", "name", "description"};
const std::vector<std::string> kGridFields{"name", "description", "keep_trees", "adaptive", "cells"};

std::string factor_list(const sim::FactorTable& factors) {
  std::vector<std::string> keys = factors.keys();
  if (keys.size() < 2) return core::join(keys, "");
  const std::string last = keys.back();
  keys.pop_back();
  return core::join(keys, ", ") + " or " + last;
}

std::string max_cells_message(long long max_cells) {
  return fmt::format("max_cells must lie in [1, {}], got {}", kMaxCampaignCells, max_cells);
}

std::string campaign_too_large_message(double cells) {
  return fmt::format(
      "the campaign's grids have {:.0f} cells, more than the {} a campaign may hold even with "
      "--force; split the domain into several campaigns",
      cells, kMaxCampaignCells);
}

std::string too_many_cells_message(const std::string& grid, double cells, std::size_t max_cells) {
  return fmt::format("grid '{}' has {:.0f} cells, more than the maximum {}; raise max_cells or pass --force", grid,
                     cells, max_cells);
}

// A grid as written: where its factors and its cells list stand, for messages.
struct GridNodes {
  core::YamlNode grid;
  std::optional<core::YamlNode> cells;
  std::optional<core::YamlNode> adaptive;
  std::vector<std::optional<core::YamlNode>> factors;  ///< per factor of the scenario
};

// Reads the shape of a grid: its fields, factor values and cells. Whether they make a valid grid
// is validate()'s question; only the size of a product is checked here, before it is expanded.
GridSpec read_grid(const core::YamlNode& node, const sim::FactorTable& table, std::size_t max_cells, bool force,
                   std::size_t cells_before, GridNodes& nodes) {
  if (!node.is_map()) node.fail("expected a grid (a mapping with name and factors), got " + node.describe());
  GridSpec grid;
  grid.where = node.location();
  std::vector<std::vector<double>> factors(table.size());
  nodes.factors.assign(table.size(), std::nullopt);
  bool named = false;
  for (const auto& [key, value] : node.entries()) {
    const std::string k = key.as_string();
    if (k == "name") {
      grid.name = value.as_string();
      named = true;
    } else if (k == "cells") {
      nodes.cells = value;
    } else if (k == "description") {
      (void)value.as_string();
    } else if (k == "keep_trees") {
      grid.keep_trees = value.as_bool();
    } else if (k == "adaptive") {
      grid.adaptive = value.as_bool();
      nodes.adaptive = value;
    } else if (auto f = table.find(k)) {
      factors[*f] = core::expand_values(value, table[*f].levels);
      nodes.factors[*f] = value;
    } else {
      std::vector<std::string> known(kGridFields.begin(), kGridFields.end());
      const std::vector<std::string> keys = table.keys();
      known.insert(known.end(), keys.begin(), keys.end());
      key.fail("unknown grid field '" + k + "'" + core::did_you_mean(k, known) + "; expected " +
               core::join(kGridFields, ", ") + " or a factor (" + factor_list(table) + ")");
    }
  }
  if (!named) node.fail("a grid needs a 'name'");

  const sim::CellInput base = table.defaults();
  if (nodes.cells && grid.adaptive)
    nodes.adaptive->fail(
        fmt::format("grid '{}' lists its cells: adaptive needs a product grid (factors with "
                    "levels), whose neighbouring cells the search can compare",
                    grid.name));
  if (nodes.cells) {
    // Grid-level factors are the defaults of every listed cell, so they must be single values.
    sim::CellInput defaults = base;
    for (std::size_t f = 0; f < table.size(); ++f) {
      if (!nodes.factors[f]) continue;
      if (factors[f].size() != 1)
        nodes.factors[f]->fail(
            fmt::format("grid '{}' lists its cells: {} at grid level must be one value (the default of every cell)",
                        grid.name, table[f].key));
      defaults[f] = factors[f][0];
    }
    for (const auto& element : nodes.cells->elements()) {
      if (cells_before + grid.cells.size() >= kMaxCampaignCells)
        element.fail(campaign_too_large_message(static_cast<double>(kMaxCampaignCells + 1)));
      if (!element.is_map()) element.fail("expected a cell (a mapping of factors), got " + element.describe());
      sim::CellInput cell = defaults;
      for (const auto& [key, value] : element.entries()) {
        const std::string k = key.as_string();
        if (k == "name" || k == "description") {
          (void)value.as_string();  // a label for readers of the campaign file
          continue;
        }
        const auto f = table.find(k);
        if (!f) key.fail("unknown factor '" + k + "'; expected " + factor_list(table) + " (or name, description)");
        // One value (a level by name for a categorical factor); a list or a range is refused.
        cell[*f] = value.is_scalar() ? core::expand_values(value, table[*f].levels).front() : scalar_number(value);
      }
      grid.cells.push_back(cell);
    }
    return grid;
  }

  double count = 1.0;
  for (std::size_t f = 0; f < table.size(); ++f) {
    if (!nodes.factors[f]) factors[f] = {base[f]};
    count *= static_cast<double>(factors[f].size());
  }
  if (count > static_cast<double>(max_cells) && !force) node.fail(too_many_cells_message(grid.name, count, max_cells));
  if (count + static_cast<double>(cells_before) > static_cast<double>(kMaxCampaignCells))
    node.fail(campaign_too_large_message(count + static_cast<double>(cells_before)));
  grid.cells.reserve(static_cast<std::size_t>(count));
  grid.levels = factors;
  // The cartesian product, the last factor varying fastest: an odometer over the level positions.
  std::vector<std::size_t> at(table.size(), 0);
  for (std::size_t n = static_cast<std::size_t>(count); n-- > 0;) {
    sim::CellInput cell = base;
    for (std::size_t f = 0; f < table.size(); ++f) cell[f] = factors[f][at[f]];
    grid.cells.push_back(cell);
    for (std::size_t f = table.size(); f-- > 0;) {
      if (++at[f] < factors[f].size()) break;
      at[f] = 0;
    }
  }
  return grid;
}

// A cell of a product grid that the simulator rejects: the first factor value that is bad on its
// own (the other factors at their defaults) is the culprit, reported at that factor's node;
// otherwise the grid.
[[noreturn]] void fail_in_product(const GridNodes& nodes, const GridSpec& grid, const sim::FactorTable& table,
                                  const std::string& message) {
  for (std::size_t f = 0; f < nodes.factors.size(); ++f) {
    if (!nodes.factors[f]) continue;
    for (double v : core::expand_values(*nodes.factors[f], table[f].levels)) {
      sim::CellInput cell = table.defaults();
      cell[f] = v;
      try {
        table.validate(cell);
      } catch (const UsageError& e) {
        nodes.factors[f]->fail(fmt::format("grid '{}': {}", grid.name, e.what()));
      }
    }
  }
  nodes.grid.fail(message);
}

}  // namespace

void validate(const Campaign& campaign, bool force) {
  core::Validator v("campaign");
  v.field("scene", campaign.scene);
  {
    const core::Validator::Scope strategies(v, "strategies");
    std::set<std::string> listed;
    for (std::size_t i = 0; i < campaign.strategies.size(); ++i) {
      const core::Validator::Scope element(v, i);
      const std::string& name = campaign.strategies[i];
      try {
        sim::validate_strategy(name);
      } catch (const UsageError& e) {
        v.fail({}, e.what());
      }
      if (!listed.insert(name).second) v.fail({}, "strategy '" + name + "' is listed twice");
    }
    if (campaign.strategies.empty()) v.fail({}, "the list of strategies is empty");
  }
  if (campaign.max_cells < 1 || campaign.max_cells > kMaxCampaignCells)
    v.fail("max_cells", max_cells_message(static_cast<long long>(campaign.max_cells)));
  std::size_t total = 0;
  for (const GridSpec& grid : campaign.grids) total += grid.cells.size();
  if (total > kMaxCampaignCells) v.fail("grids", campaign_too_large_message(static_cast<double>(total)));
  const core::Validator::Scope grids(v, "grids");
  const sim::FactorTable table = sim::scenario_factors(campaign.scene);
  std::set<std::string> names;
  for (std::size_t i = 0; i < campaign.grids.size(); ++i) {
    const core::Validator::Scope at(v, i);
    const GridSpec& grid = campaign.grids[i];
    if (grid.name.empty()) v.fail("name", "a grid name must not be empty");
    if (grid.cells.empty()) v.fail("cells", fmt::format("grid '{}' has an empty cells list", grid.name));
    if (grid.cells.size() > campaign.max_cells && !force)
      v.fail({}, too_many_cells_message(grid.name, static_cast<double>(grid.cells.size()), campaign.max_cells));
    if (!grid.seeds.empty() && grid.seeds.size() != grid.cells.size())
      v.fail("seeds",
             fmt::format("grid '{}' has {} seeds for {} cells", grid.name, grid.seeds.size(), grid.cells.size()));
    {
      const core::Validator::Scope cells(v, "cells");
      for (std::size_t j = 0; j < grid.cells.size(); ++j) {
        try {
          table.validate(grid.cells[j]);
        } catch (const UsageError& e) {
          const core::Validator::Scope cell(v, j);
          v.fail({}, fmt::format("grid '{}': {}", grid.name, e.what()));
        }
      }
    }
    if (!names.insert(grid.name).second) v.fail({}, "duplicate grid name '" + grid.name + "'");
  }
  if (campaign.grids.empty()) v.fail({}, "a campaign needs at least one grid");
}

Campaign parse_campaign(const std::string& text, const std::string& file_name, const std::filesystem::path& base_dir,
                        bool force) {
  const core::YamlNode root = core::YamlNode::parse(text, file_name);
  if (!root.is_map())
    root.fail("expected a campaign (a mapping with scene, seed, strategies, grids), got " + root.describe());
  Campaign campaign;
  campaign.file = file_name;
  campaign.text = text;
  std::optional<core::YamlNode> grids_node;
  for (const auto& [key, value] : root.entries()) {
    const std::string k = key.as_string();
    if (k == "scene") {
      if (value.is_null()) continue;
      campaign.scene_file = value.as_string();
      std::filesystem::path scene_path = *campaign.scene_file;
      if (scene_path.is_relative()) scene_path = base_dir / scene_path;
      if (!std::filesystem::is_regular_file(scene_path))
        value.fail("scene file '" + scene_path.string() + "' does not exist");
      campaign.scene = sim::load_scene_config(scene_path);
    } else if (k == "seed") {
      const long long seed = value.as_int();
      if (seed < 0) value.fail(fmt::format("seed must be >= 0, got {}", seed));  // an unsigned field
      campaign.seed = static_cast<std::uint64_t>(seed);
    } else if (k == "strategies") {
      campaign.strategies.clear();
      for (const auto& element : value.elements()) campaign.strategies.push_back(element.as_string());
    } else if (k == "max_cells") {
      // Checked at once: the grids below are expanded only up to this limit.
      const long long max = value.as_int();
      if (max < 1 || max > static_cast<long long>(kMaxCampaignCells)) value.fail(max_cells_message(max));
      campaign.max_cells = static_cast<std::size_t>(max);
    } else if (k == "grids") {
      grids_node = value;
    } else if (k == "name" || k == "description") {
      (void)value.as_string();
    } else {
      key.fail("unknown campaign field '" + k + "'" + core::did_you_mean(k, kCampaignFields) + "; expected " +
               core::join(kCampaignFields, ", "));
    }
  }
  if (!grids_node) root.fail("a campaign needs 'grids'");
  // Grids come after the scene is known: its factors, their defaults and limits come from it.
  const sim::FactorTable table = sim::scenario_factors(campaign.scene);
  std::vector<GridNodes> grid_nodes;
  std::size_t cells = 0;
  for (const auto& element : grids_node->elements()) {
    GridNodes& nodes = grid_nodes.emplace_back(GridNodes{element, std::nullopt, std::nullopt, {}});
    campaign.grids.push_back(read_grid(element, table, campaign.max_cells, force, cells, nodes));
    cells += campaign.grids.back().cells.size();
  }
  try {
    validate(campaign, force);
  } catch (const core::ConfigError& e) {
    // grids[i].cells[j] of a product grid: no node of its own, the factor values make it.
    const auto& steps = e.path().steps;
    if (steps.size() == 4 && std::get_if<std::string>(&steps[0]) && std::get<std::string>(steps[0]) == "grids" &&
        std::get_if<std::string>(&steps[2]) && std::get<std::string>(steps[2]) == "cells") {
      const auto i = std::get<std::size_t>(steps[1]);
      if (!grid_nodes[i].cells) fail_in_product(grid_nodes[i], campaign.grids[i], table, e.detail());
    }
    core::fail_at(root, e, /*with_path=*/false);
  }
  return campaign;
}

Campaign load_campaign(const std::filesystem::path& path, bool force) {
  const std::string text = core::read_input_file(path);
  return parse_campaign(text, path.string(), path.parent_path(), force);
}

std::string cell_key(const std::string& grid, const sim::CellInput& cell) {
  return fmt::format("{} {:.9g}", grid, fmt::join(cell, " "));
}

std::uint64_t cell_seed(const Campaign& campaign, const std::string& grid, const sim::CellInput& cell) {
  return sim::derive_seed(campaign.seed, cell_key(grid, cell));
}

std::uint64_t cell_seed(const Campaign& campaign, const GridSpec& grid, std::size_t index) {
  return grid.seeds.empty() ? cell_seed(campaign, grid.name, grid.cells[index]) : grid.seeds[index];
}

std::string config_hash(const Campaign& campaign) {
  // FNV-1a over a canonical text of everything that decides a cell's result.
  std::uint64_t h = 14695981039346656037ull;
  const auto feed = [&h](std::string_view text) {
    for (char c : text) {
      h ^= static_cast<unsigned char>(c);
      h *= 1099511628211ull;
    }
    h ^= 0xff;  // separator, so that "ab"+"c" and "a"+"bc" differ
    h *= 1099511628211ull;
  };
  feed(fmt::format("emrm {}", kVersion));
  feed(sim::to_yaml(campaign.scene));
  feed(fmt::format("seed {}", campaign.seed));
  feed("strategies " + core::join(campaign.strategies, " "));
  for (const auto& grid : campaign.grids) {
    feed("grid " + grid.name + (grid.keep_trees ? " keep_trees" : ""));
    for (const auto& cell : grid.cells) feed(cell_key("", cell));
    for (std::uint64_t seed : grid.seeds) feed(std::to_string(seed));
  }
  return fmt::format("{:016x}", h);
}

std::size_t total_cells(const Campaign& campaign) noexcept {
  std::size_t n = 0;
  for (const auto& grid : campaign.grids) n += grid.cells.size();
  return n;
}

namespace {

// At most `n` points of an edge, evenly spaced, first and last kept.
Polyline thin(const std::vector<sim::PathPoint>& points, std::size_t n) {
  Polyline out;
  const auto point = [](const sim::PathPoint& p) {
    return std::array<double, 4>{p.t_s, p.state.x_m, p.state.y_m, p.state.speed_mps()};
  };
  if (points.size() <= n) {
    for (const auto& p : points) out.push_back(point(p));
    return out;
  }
  for (std::size_t k = 0; k < n; ++k) out.push_back(point(points[k * (points.size() - 1) / (n - 1)]));
  return out;
}

}  // namespace

CellEvidence cell_evidence(sim::Evidence e) noexcept {
  switch (e) {
    case sim::Evidence::kWitness:
      return CellEvidence::kWitness;
    case sim::Evidence::kCertificate:
      return CellEvidence::kCertificate;
    case sim::Evidence::kUndecided:
      return CellEvidence::kUndecided;
  }
  return CellEvidence::kNone;
}

CellRecord to_record(const sim::SceneConfig& scene, const std::string& grid, std::int64_t index, std::uint64_t seed,
                     const sim::CellResult& result, bool keep_trajectories) {
  constexpr double kKph = 3.6;
  CellRecord r;
  r.grid = grid;
  r.index = index;
  r.factors = result.input;
  r.seed = seed;
  r.feasible = result.feasible;
  r.region = result.region;
  r.unmitigated_impact_speed_kph = result.unmitigated.impact_speed_mps * kKph;
  r.unmitigated_delta_v_kph = result.unmitigated.delta_v_mps * kKph;
  r.unmitigated_p_mais3 = result.unmitigated.p_mais3;
  r.unmitigated_p_fatal = result.unmitigated.p_fatal;
  r.unmitigated_loss_level = result.unmitigated.loss_level;
  if (result.feasible) r.evidence = cell_evidence(result.evidence);
  r.mitigation_evidence = result.mitigation_evidence;
  r.strengthened = result.strengthened;
  if (result.certificate) r.certificate = sim::to_json(*result.certificate, sim::scenario_factors(scene)).dump();
  r.p_mais3_reduction = result.p_mais3_reduction;
  r.p_fatal_reduction = result.p_fatal_reduction;
  for (const auto& o : result.strategies) {
    OutcomeRecord out;
    out.strategy = o.strategy;
    out.avoided = o.avoided;
    out.contact = o.contact;
    out.road_departure = o.road_departure;
    out.impact_speed_kph = o.impact.impact_speed_mps * kKph;
    out.delta_v_kph = o.impact.delta_v_mps * kKph;
    out.p_mais3 = o.impact.p_mais3;
    out.p_fatal = o.impact.p_fatal;
    out.loss_level = o.impact.loss_level;
    out.delta_loss = o.delta_loss;
    out.min_ttc_s = o.min_ttc_s;
    out.planner_nodes = o.planner.nodes;
    out.planner_rollouts = o.planner.rollouts;
    out.fsm_trace = o.fsm_trace;
    out.loss_evaluation_trace = o.loss_evaluation_trace;
    out.chosen_strategy = o.chosen_strategy;
    out.adopted_from = o.adopted_from;
    out.evidence = o.evidence;
    out.maneuver = sim::to_json(o.maneuver).dump();
    if (keep_trajectories) {
      // Enough of each tree to draw it: at most 400 edges of each kind, evenly chosen, 4 points each.
      constexpr std::size_t kEdges = 400;
      out.path = thin(o.path, o.path.size());
      for (const bool fail_safe : {false, true}) {
        std::vector<const sim::TreeEdge*> edges;
        for (const auto& edge : o.tree)
          if (edge.fail_safe == fail_safe) edges.push_back(&edge);
        auto& into = fail_safe ? out.failsafe_tree : out.goal_tree;
        const std::size_t n = std::min(edges.size(), kEdges);
        for (std::size_t k = 0; k < n; ++k) into.push_back(thin(edges[k * edges.size() / n]->points, 4));
      }
    }
    r.outcomes.push_back(std::move(out));
  }
  return r;
}

std::filesystem::path scene_folder(const Campaign& campaign) {
  std::filesystem::path campaign_dir = std::filesystem::path(campaign.file).parent_path();
  if (!campaign.scene_file) return campaign_dir;
  const std::filesystem::path scene = *campaign.scene_file;
  return (scene.is_relative() ? campaign_dir / scene : scene).parent_path();
}

void apply_profile(Campaign& campaign, const std::string& profile) {
  sim::apply_profile(campaign.scene, profile, scene_folder(campaign));
}

}  // namespace emrm::campaign
