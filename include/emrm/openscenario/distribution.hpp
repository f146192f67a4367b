#pragma once

// A ParameterValueDistribution file (OpenSCENARIO 1.1+): the values a scenario's parameters take
// across a set of concrete scenarios. Deterministic distributions are read; stochastic ones are
// refused (not supported yet).

#include <filesystem>
#include <map>
#include <string>
#include <variant>
#include <vector>

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
};

/// A DeterministicMultiParameterDistribution's ValueSetDistribution: sets of assignments, each a
/// concrete scenario.
using ValueSets = std::vector<std::map<std::string, std::string>>;

struct ParameterDistribution {
  std::filesystem::path scenario_file;  ///< ScenarioFile filepath, relative paths against the file's folder
  std::vector<SingleParameterValues> single;
  std::vector<ValueSets> multi;
};

/// Reads a ParameterValueDistribution file (XSD-validated). Throws InputError at the element for a
/// Stochastic distribution ("not supported"), an empty or inverted range, a step <= 0.
[[nodiscard]] ParameterDistribution load_parameter_distribution(const std::filesystem::path& file);

}  // namespace emrm::openscenario
