#pragma once

// Reading an OpenSCENARIO 1.0-1.3 scenario (.xosc) with its OpenDRIVE road network: the supported
// subset (supported.hpp, docs/import.md "OpenSCENARIO").

#include <filesystem>

#include "emrm/openscenario/parameters.hpp"
#include "emrm/openscenario/scenario.hpp"

namespace emrm::openscenario {

/// What load_openscenario reads a scenario with.
struct ReadOptions {
  ParameterOverrides overrides;  ///< declared parameters' values replacing their defaults
  /// The entity emrm drives (`emrm import --ego`): it alone may have a controller other than
  /// esmini's default. Empty: default_ego's choice.
  std::string ego;
};

/// The ego when none is named: the entity named Ego, ego or hero, else the first vehicle; nullptr
/// when there is neither.
[[nodiscard]] const Entity* default_ego(const std::vector<Entity>& entities);

/// Reads `file`: validates it against the OpenSCENARIO XSD (xml::validate) first, then declares
/// its global parameters (each `options.overrides` entry replacing a declared default: an override naming
/// no declared parameter is an InputError), reads the RoadNetwork's LogicFile relative to the
/// scenario's folder (opendrive::load_opendrive), the entities (catalog references resolved through
/// the CatalogLocations, relative to the scenario's folder) and the storyboard. Every number is
/// range-checked; a reference to an entity, road, lane or storyboard element that does not exist,
/// and every element outside the supported subset, is an InputError at the referring element
/// (file:line:column); so is a controller other than esmini's default on any entity but the ego,
/// and an `options.ego` naming no entity.
[[nodiscard]] Scenario load_openscenario(const std::filesystem::path& file, const ReadOptions& options = {});

/// The global parameters `file` declares, with their types and defaults (resolved), for a family
/// to turn into factors; reads only the document (no road network, no storyboard).
[[nodiscard]] std::vector<Parameter> declared_parameters(const std::filesystem::path& file);

}  // namespace emrm::openscenario
