#pragma once

// A ParameterValueDistribution file (OpenSCENARIO 1.1+): the values a scenario's parameters take
// across a set of concrete scenarios. Deterministic distributions are read; stochastic ones are
// refused (not supported yet).

#include <filesystem>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "emrm/core/error.hpp"

namespace emrm::openscenario {

/// DistributionRange: lower, lower + step, ..., up to upper.
struct ValueRange {
  double lower = 0.0;
  double upper = 0.0;
  double step = 0.0;
  /// Every value of the range (the upper limit included when a step lands on it within 1e-9).
  [[nodiscard]] std::vector<double> values() const;
};

/// One DeterministicSingleParameterDistribution: a range or a set of values (as texts).
struct SingleParameterValues {
  std::string parameter;
  std::variant<ValueRange, std::vector<std::string>> values;
  SourceLocation where;  ///< the distribution element
};

/// A DeterministicMultiParameterDistribution's ValueSetDistribution: sets of assignments
/// (parameter → value text), each a concrete scenario.
struct ValueSets {
  std::vector<std::map<std::string, std::string>> sets;
  SourceLocation where;  ///< the distribution element
};

struct ParameterDistribution {
  std::filesystem::path file;           ///< the distribution file
  std::filesystem::path scenario_file;  ///< ScenarioFile filepath, relative paths against the file's folder
  SourceLocation scenario_where;        ///< the ScenarioFile element
  std::vector<SingleParameterValues> single;
  std::vector<ValueSets> multi;
};

/// Whether the file is an OpenSCENARIO document holding a ParameterValueDistribution (rather than a
/// scenario or a catalog). Throws InputError for a file that is no XML.
[[nodiscard]] bool is_parameter_distribution(const std::filesystem::path& file);

/// Reads a ParameterValueDistribution file (XSD-validated). Throws InputError at the element for a
/// Stochastic distribution ("not supported"), an empty or inverted range, a step <= 0.
[[nodiscard]] ParameterDistribution load_parameter_distribution(const std::filesystem::path& file);

}  // namespace emrm::openscenario
