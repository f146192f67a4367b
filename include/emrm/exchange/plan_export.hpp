#pragma once

// A plan exported to OpenSCENARIO (docs/openscenario.md, "Exporting a plan"): the T-junction's as one
// logical scenario — its positions and speeds as expressions of parameters, a value-set distribution
// of one parameter set per planned scenario, and the road networks they need —, every other
// family's as one concrete scenario per planned scenario beside its road.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "emrm/exchange/openscenario.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::exchange {

/// The T-junction's plan as a logical scenario (`logical`): DIR/tjunction.xosc (ParameterDeclarations,
/// positions and speeds as expressions of them), DIR/tjunction_distribution.xosc (a deterministic
/// ValueSetDistribution, one ParameterValueSet per scenario) and one road network per distinct
/// junction position in DIR/roads/. Every other family's: DIR/ID/FAMILY.xosc and DIR/ID/FAMILY.xodr
/// for each scenario ID of the plan. Written all or none.
struct PlanExport {
  std::vector<std::filesystem::path> files;
  std::size_t scenarios = 0;
  std::size_t road_networks = 0;
  bool logical = false;
};
/// Throws InputError at the scenario's row for a scenario the scene rejects or that is infeasible,
/// and (other families) for an id that cannot name a folder.
PlanExport export_plan(const std::filesystem::path& dir, const sim::SceneConfig& config,
                       const scenario::ScenarioFile& scenarios, const ExportOptions& options);

/// Names of the logical scenario's parameters, in declaration order: the cell's factors, then
/// road_network (the .xodr file) and scenario_id.
[[nodiscard]] std::vector<std::string> plan_parameter_names(const sim::FactorTable& factors);

}  // namespace emrm::exchange
