// ParameterValueDistribution files (distribution.hpp).

#include "emrm/openscenario/distribution.hpp"

#include <fmt/format.h>

#include <cmath>

#include "emrm/core/error.hpp"
#include "emrm/xml/document.hpp"

namespace emrm::openscenario {

std::vector<double> ValueRange::values() const {
  std::vector<double> out;
  const auto n = static_cast<long>(std::floor((upper - lower) / step + 1e-9));
  for (long i = 0; i <= n; ++i) out.push_back(lower + static_cast<double>(i) * step);
  return out;
}

bool is_parameter_distribution(const std::filesystem::path& file) {
  return xml::Document::load(file).root().child("ParameterValueDistribution").has_value();
}

ParameterDistribution load_parameter_distribution(const std::filesystem::path& file) {
  const xml::Document document = xml::Document::load(file);
  xml::validate(document, xml::Schema::kOpenScenario);
  const xml::Element root = document.root();
  const auto distribution = root.child("ParameterValueDistribution");
  if (!distribution) root.fail("expected a ParameterValueDistribution (this file is a scenario or a catalog)");
  ParameterDistribution out;
  out.file = file;
  const xml::Element scenario = distribution->required_child("ScenarioFile");
  out.scenario_file = file.parent_path() / scenario.required("filepath");
  out.scenario_where = scenario.where();
  if (const auto stochastic = distribution->child("Stochastic"))
    stochastic->fail("Stochastic is not supported (supported: Deterministic)");
  const xml::Element deterministic = distribution->required_child("Deterministic");
  for (const xml::Element& d : deterministic.children()) {
    if (d.name() == "DeterministicMultiParameterDistribution") {
      ValueSets sets{{}, d.where()};
      for (const xml::Element& set : d.required_child("ValueSetDistribution").children("ParameterValueSet")) {
        std::map<std::string, std::string> assignment;
        for (const xml::Element& a : set.children("ParameterAssignment"))
          assignment[a.required("parameterRef")] = a.required("value");
        sets.sets.push_back(std::move(assignment));
      }
      out.multi.push_back(std::move(sets));
      continue;
    }
    SingleParameterValues single{d.required("parameterName"), std::vector<std::string>{}, d.where()};
    if (const auto range = d.child("DistributionRange")) {
      const xml::Element limits = range->required_child("Range");
      ValueRange r{limits.number("lowerLimit"), limits.number("upperLimit"), range->number("stepWidth")};
      if (!(r.step > 0.0)) range->fail("stepWidth", fmt::format("stepWidth: expected a step > 0, got {}", r.step));
      if (r.upper < r.lower)
        limits.fail("upperLimit",
                    fmt::format("upperLimit: expected at least lowerLimit ({}), got {}", r.lower, r.upper));
      single.values = r;
    } else if (const auto set = d.child("DistributionSet")) {
      std::vector<std::string> values;
      for (const xml::Element& element : set->children("Element")) values.push_back(element.required("value"));
      single.values = std::move(values);
    } else {
      d.fail(fmt::format(
          "{} is not supported in DeterministicSingleParameterDistribution (supported: "
          "DistributionRange, DistributionSet)",
          d.children().empty() ? std::string("an empty distribution") : std::string(d.children().front().name())));
    }
    out.single.push_back(std::move(single));
  }
  return out;
}

}  // namespace emrm::openscenario
