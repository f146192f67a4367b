#pragma once

// Reading an OpenSCENARIO 1.0-1.3 scenario (.xosc) with its OpenDRIVE road network: the supported
// subset (supported.hpp, docs/import.md "OpenSCENARIO").

#include <filesystem>

#include "emrm/openscenario/parameters.hpp"
#include "emrm/openscenario/scenario.hpp"

namespace emrm::openscenario {

/// Reads `file`: validates it against the OpenSCENARIO XSD (xml::validate) first, then declares
/// its global parameters (each `overrides` entry replacing a declared default: an override naming
/// no declared parameter is an InputError), reads the RoadNetwork's LogicFile relative to the
/// scenario's folder (opendrive::load_opendrive), the entities (catalog references resolved through
/// the CatalogLocations, relative to the scenario's folder) and the storyboard. Every number is
/// range-checked; a reference to an entity, road, lane or storyboard element that does not exist,
/// and every element outside the supported subset, is an InputError at the referring element
/// (file:line:column).
[[nodiscard]] Scenario load_openscenario(const std::filesystem::path& file, const ParameterOverrides& overrides = {});

/// The global parameters `file` declares, with their types and defaults (resolved), for a family
/// to turn into factors; reads only the document (no road network, no storyboard).
[[nodiscard]] std::vector<Parameter> declared_parameters(const std::filesystem::path& file);

}  // namespace emrm::openscenario
