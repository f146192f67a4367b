#pragma once

// What the exporters share (opendrive.cpp, openscenario.cpp, plan_export.cpp): the files' fixed date
// and number format, and the parts of a scenario document the plan export builds on. Internal to
// src/exchange.

#include <string>
#include <utility>
#include <vector>

#include "emrm/exchange/openscenario.hpp"
#include "emrm/sim/factors.hpp"
#include "emrm/sim/scene.hpp"
#include "xml_writer.hpp"

namespace emrm::exchange::detail {

// A fixed date keeps the export reproducible (the files are compared in tests and by diff).
inline constexpr const char* kDate = "2026-01-01T00:00:00";

inline std::string num(double x) { return xml_number(x); }

// The OpenSCENARIO FileHeader, with the fixed date and emrm's version, and `properties` (name,
// value) when there are any.
void file_header(XmlWriter& x, const std::string& description,
                 const std::vector<std::pair<std::string, std::string>>& properties = {});
// A concrete scenario's FileHeader: its cell's factors, road file and id as properties
// (scenario_fields, xosc_parts.hpp).
void cell_header(XmlWriter& x, const std::string& description, const sim::FactorTable& factors,
                 const sim::CellInput& cell, const std::string& road_file, const std::string& scenario_id);

// One cell's scenario document; `parametric`: the logical scenario, its positions and speeds as
// expressions of its parameters (the cell gives their default values).
// `truck_rest_s`: when the truck comes to rest (the latest over the scenarios a logical scenario
// stands for), infinite when it does not brake.
std::string scenario_xml(const sim::SceneConfig& config, const sim::CellInput& cell, const EgoTrajectory* trajectory,
                         const ExportOptions& options, const std::string& road_file, bool parametric,
                         const std::string& scenario_id, double truck_rest_s);

// One cell of a family other than the T-junction (family_scenario.cpp): the ego and every actor
// of the cell, each actor's motion as a timed trajectory; `scenario_id` its parameter scenario_id.
std::string family_scenario_xml(const sim::SceneConfig& config, const sim::CellInput& cell,
                                const EgoTrajectory* trajectory, const ExportOptions& options,
                                const std::string& road_file, const std::string& scenario_id);

// When the cell's truck comes to rest (infinite when it does not brake).
double truck_rest_s(const sim::SceneConfig& config, const sim::CellInput& cell);

// Throws UsageError for a cell the scene rejects or that is infeasible.
void require_feasible(const sim::SceneConfig& config, const sim::CellInput& cell);

}  // namespace emrm::exchange::detail
