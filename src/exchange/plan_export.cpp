// A plan as a logical scenario (plan_export.hpp).

#include "emrm/exchange/plan_export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <map>

#include "emrm/campaign/campaign.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/sim/family.hpp"
#include "export_support.hpp"
#include "xml_writer.hpp"

namespace emrm::exchange {
namespace {

namespace fs = std::filesystem;
using detail::family_scenario_xml;
using detail::file_header;
using detail::num;
using detail::require_feasible;
using detail::scenario_xml;
using detail::truck_rest_s;

std::string junction_road_file(const JunctionLayout& l) {
  return fmt::format("{}/tjunction_x{:.3f}.xodr", kRoadsFolder, l.side_road_x_m);
}

}  // namespace

std::vector<std::string> plan_parameter_names(const sim::FactorTable& factors) {
  std::vector<std::string> names = factors.keys();
  names.insert(names.end(), {"road_network", "scenario_id"});
  return names;
}

namespace {

struct Concrete {
  std::string id;
  sim::CellInput cell;
  std::string road_file;
};

// Every planned scenario as a cell of the scene; exit 2 at the row of one it rejects.
std::vector<Concrete> concrete_scenarios(const sim::SceneConfig& config, const scenario::ScenarioFile& scenarios) {
  if (scenarios.rows.empty()) throw InputError({scenarios.file, 1, 1}, "expected at least one scenario in the plan");
  const sim::FactorTable factors = sim::scenario_factors(config);
  std::vector<Concrete> out;
  for (const auto& row : scenarios.rows) {
    sim::CellInput cell = factors.defaults();
    for (std::size_t i = 0; i < scenarios.factors.size(); ++i)
      (void)factors.set(cell, scenarios.factors[i], row.values[i]);
    try {
      require_feasible(config, cell);
    } catch (const UsageError& e) {
      throw InputError(row.where, fmt::format("scenario {}: {}", row.id, e.what()));
    }
    out.push_back({row.id, cell, {}});
  }
  return out;
}

// The T-junction's plan: one logical scenario, its value-set distribution and its road networks.
PlanExport export_logical_plan(const fs::path& dir, const sim::SceneConfig& config,
                               const scenario::ScenarioFile& scenarios, const ExportOptions& options) {
  std::vector<Concrete> concrete = concrete_scenarios(config, scenarios);
  std::map<std::string, sim::CellInput> roads;  // file -> the cell whose road network it is
  const sim::FactorTable factors = sim::scenario_factors(config);
  for (auto& c : concrete) {
    const JunctionLayout layout = junction_layout(config, c.cell);
    c.road_file = junction_road_file(layout);
    // Scenarios sharing a junction share its road network: the one whose side road reaches furthest
    // (its truck starts highest), so that every truck of the group starts on it.
    const auto [it, added] = roads.emplace(c.road_file, c.cell);
    if (!added && junction_layout(config, it->second).side_road_length_m < layout.side_road_length_m)
      it->second = c.cell;
  }
  std::vector<core::FileContent> files;
  double rest_s = 0.0;
  for (const auto& c : concrete) rest_s = std::max(rest_s, truck_rest_s(config, c.cell));
  files.push_back({dir / kScenarioFile, scenario_xml(config, concrete.front().cell, nullptr, options,
                                                     concrete.front().road_file, true, concrete.front().id, rest_s)});
  XmlWriter x;
  x.open("OpenSCENARIO");
  file_header(x, fmt::format("{}: the {} concrete scenarios of an emrm plan ({})", config.name, concrete.size(),
                             fs::path(scenarios.file).filename().string()));
  x.open("ParameterValueDistribution");
  x.leaf("ScenarioFile", {{"filepath", kScenarioFile}});
  x.open("Deterministic");
  x.open("DeterministicMultiParameterDistribution");
  x.open("ValueSetDistribution");
  for (const auto& c : concrete) {
    x.open("ParameterValueSet");
    std::vector<std::string> values;
    for (const double v : c.cell) values.push_back(num(v));
    values.insert(values.end(), {c.road_file, c.id});
    const auto names = plan_parameter_names(factors);
    for (std::size_t i = 0; i < names.size(); ++i)
      x.leaf("ParameterAssignment", {{"parameterRef", names[i]}, {"value", values[i]}});
    x.close();
  }
  x.close();
  x.close();
  x.close();
  x.close();
  x.close();
  files.push_back({dir / kDistributionFile, std::move(x).str()});
  for (const auto& [file, cell] : roads) files.push_back({dir / file, opendrive_xml(config, cell)});
  core::write_files(files);

  PlanExport out;
  out.scenarios = concrete.size();
  out.road_networks = roads.size();
  out.logical = true;
  for (const auto& f : files) out.files.push_back(f.path);
  return out;
}

// A scenario id names its folder: letters, digits, '-', '_' and '.', not only dots.
void require_folder_name(const scenario::ScenarioRow& row) {
  const bool safe = std::all_of(row.id.begin(), row.id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_' || c == '.';
  });
  if (!safe || row.id.find_first_not_of('.') == std::string::npos)
    throw InputError(row.where, fmt::format("scenario id '{}' cannot name a folder of the export: expected letters, "
                                            "digits, '-', '_' and '.'",
                                            row.id));
}

// Every other family's plan: each scenario a concrete document beside its own road, in a folder
// named by its id (the actors' motions are the cell's own, not expressions of its parameters).
PlanExport export_concrete_plan(const fs::path& dir, const sim::SceneConfig& config,
                                const scenario::ScenarioFile& scenarios, const ExportOptions& options) {
  for (const auto& row : scenarios.rows) require_folder_name(row);
  const std::vector<Concrete> concrete = concrete_scenarios(config, scenarios);
  const std::string road = road_file_of(config);
  std::vector<core::FileContent> files;
  for (const auto& c : concrete) {
    files.push_back({dir / c.id / road, straight_road_xml(config, c.cell)});
    files.push_back(
        {dir / c.id / scenario_file_of(config), family_scenario_xml(config, c.cell, nullptr, options, road, c.id)});
  }
  core::write_files(files);
  PlanExport out;
  out.scenarios = concrete.size();
  out.road_networks = concrete.size();
  for (const auto& f : files) out.files.push_back(f.path);
  return out;
}

}  // namespace

PlanExport export_plan(const fs::path& dir, const sim::SceneConfig& config, const scenario::ScenarioFile& scenarios,
                       const ExportOptions& options) {
  if (sim::has_tjunction_analytics(config)) return export_logical_plan(dir, config, scenarios, options);
  return export_concrete_plan(dir, config, scenarios, options);
}

}  // namespace emrm::exchange
