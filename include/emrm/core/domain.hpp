#pragma once

// Parameter domains as written in YAML: one value, a list, or a range {from, to, step} or
// {from, to, levels}. Used by campaign grids and by the manual baseline grid of an ODD file.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "emrm/core/yaml.hpp"

namespace emrm::core {

/// The most values one factor may take (a list, a range's steps or levels): a grid's size is checked
/// against its limit before it is expanded, and no factor alone may hold more than this.
inline constexpr std::size_t kMaxFactorValues = 1'000'000;

/// Rounded to 1e-9, so that 0.25 + 0.06·k is written, hashed and seeded as the number a user reads.
[[nodiscard]] double round_1e9(double x) noexcept;

/// A number at `node`; throws InputError when it is not a finite number.
[[nodiscard]] double scalar_number(const YamlNode& node);

/// The values of one factor as written: a number, a list, {from, to, step} or {from, to, levels}.
/// Ranges are from + i·step (to included within 1e-9 relative) and levels are evenly spaced from
/// `from` to `to`; every value is rounded to 1e-9. Throws InputError at `node` when malformed
/// (empty list, reversed range, step <= 0, levels < 1, more than kMaxFactorValues values, unknown
/// range field).
[[nodiscard]] std::vector<double> expand_values(const YamlNode& node);
/// The same for a factor whose values are named `levels` (a categorical factor; none: a number): a
/// level's name or a list of names, each read as its index. Throws InputError at the node for a name
/// that is not a level, or a range.
[[nodiscard]] std::vector<double> expand_values(const YamlNode& node, std::span<const std::string> levels);

}  // namespace emrm::core
