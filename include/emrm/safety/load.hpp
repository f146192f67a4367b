#pragma once

#include <filesystem>
#include <string>

#include "emrm/safety/model.hpp"

namespace emrm::safety {

/// Reads a safety case from a YAML file (schema: docs/safety-yaml.md) and validates what makes
/// it unreadable as data. Throws InputError, naming file:line:column, for: malformed YAML, a
/// wrong type, a missing or unknown field, a rating out of range, an unknown UCA type, an empty
/// or duplicate id (ids are unique across all entities), a factor with min > max, a region that
/// is not a valid expression or names an undeclared factor, a SMIL level not in `smil.levels`.
/// Inconsistencies between entities (dangling references and the like) are not thrown: they
/// are findings of check().
[[nodiscard]] SafetyCase load_safety_case(const std::filesystem::path& path);

/// As load_safety_case, from text; `file_name` is used in messages.
[[nodiscard]] SafetyCase parse_safety_case(const std::string& text, const std::string& file_name);

/// The case as YAML text (the effective safety case, as emrm understood it).
[[nodiscard]] std::string to_yaml(const SafetyCase& safety_case);

}  // namespace emrm::safety
