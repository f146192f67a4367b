#include "emrm/core/domain.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace emrm::core {
namespace {

[[noreturn]] void too_many_values(const YamlNode& element) {
  element.fail(fmt::format("the list has more than the {} values a factor may have", kMaxFactorValues));
}

std::vector<double> expand_range(const YamlNode& node) {
  std::optional<YamlNode> from, to, step, levels;
  for (const auto& [key, value] : node.entries()) {
    const std::string k = key.as_string();
    if (k == "from")
      from = value;
    else if (k == "to")
      to = value;
    else if (k == "step")
      step = value;
    else if (k == "levels")
      levels = value;
    else
      key.fail("unknown range field '" + k + "'; expected from, to and step or levels");
  }
  if (!from || !to) node.fail("a range needs 'from' and 'to' (and 'step' or 'levels')");
  if (step.has_value() == levels.has_value()) node.fail("a range needs exactly one of 'step' or 'levels'");
  const double lo = scalar_number(*from);
  const double hi = scalar_number(*to);
  if (hi < lo) node.fail(fmt::format("reversed range: 'to' ({:g}) is below 'from' ({:g})", hi, lo));
  std::vector<double> values;
  if (step) {
    const double dx = scalar_number(*step);
    if (!(dx > 0.0)) step->fail(fmt::format("step must be > 0, got {:g}", dx));
    const double q = (hi - lo) / dx;
    // `to` counts as reached within 1e-9 relative: 0.25 + 45·0.06 is 2.9500000000000002.
    const double n = std::floor(q + 1e-9 * std::max(1.0, q));
    if (n + 1 > static_cast<double>(kMaxFactorValues))
      node.fail(fmt::format("the range has {:g} values, more than the {} a factor may have; use a larger step", n + 1,
                            kMaxFactorValues));
    for (long long i = 0; i <= static_cast<long long>(n); ++i)
      values.push_back(round_1e9(lo + static_cast<double>(i) * dx));
  } else {
    const long long count = levels->as_int();
    if (count < 1) levels->fail(fmt::format("levels must be >= 1, got {}", count));
    if (count > static_cast<long long>(kMaxFactorValues))
      levels->fail(fmt::format("levels must be <= {} (a factor's most values), got {}", kMaxFactorValues, count));
    if (count == 1) {
      if (hi != lo) levels->fail("levels 1 needs from == to");
      values.push_back(round_1e9(lo));
    } else {
      for (long long i = 0; i < count; ++i)
        values.push_back(round_1e9(lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(count - 1)));
    }
  }
  return values;
}

}  // namespace

double round_1e9(double x) noexcept { return std::round(x * 1e9) / 1e9; }

double scalar_number(const YamlNode& node) {
  if (!node.is_scalar()) node.fail("expected a number, got " + node.describe());
  return node.as_double();
}

std::vector<double> expand_values(const YamlNode& node) {
  if (node.is_scalar()) return {round_1e9(node.as_double())};
  if (node.is_sequence()) {
    std::vector<double> values;
    for (const auto& element : node.elements()) {
      if (values.size() == kMaxFactorValues) too_many_values(element);
      values.push_back(round_1e9(scalar_number(element)));
    }
    if (values.empty()) node.fail("empty list of values");
    return values;
  }
  if (node.is_map()) return expand_range(node);
  node.fail("expected a value, a list, {from, to, step} or {from, to, levels}, got " + node.describe());
}

std::vector<double> expand_values(const YamlNode& node, std::span<const std::string> levels) {
  if (levels.empty()) return expand_values(node);
  const auto level_of = [&](const YamlNode& element) {
    if (element.is_scalar()) {
      const std::string name = element.as_string();
      for (std::size_t i = 0; i < levels.size(); ++i)
        if (levels[i] == name) return static_cast<double>(i);
    }
    element.fail(fmt::format("expected one of the levels {}, got {}", fmt::join(levels, ", "), element.describe()));
  };
  if (node.is_sequence()) {
    std::vector<double> values;
    for (const auto& element : node.elements()) {
      if (values.size() == kMaxFactorValues) too_many_values(element);
      values.push_back(level_of(element));
    }
    if (values.empty()) node.fail("empty list of values");
    return values;
  }
  return {level_of(node)};
}

}  // namespace emrm::core
