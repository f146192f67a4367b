#pragma once

// Parameter domains as written in YAML: one value, a list, or a range {from, to, step} or
// {from, to, levels}. Used by campaign grids and by the manual baseline grid of an ODD file.

#include <vector>

#include "emrm/core/yaml.hpp"

namespace emrm::core {

/// Rounded to 1e-9, so that 0.25 + 0.06·k is written, hashed and seeded as the number a user reads.
[[nodiscard]] double round_1e9(double x) noexcept;

/// A number at `node`; throws InputError when it is not a finite number.
[[nodiscard]] double scalar_number(const YamlNode& node);

/// The values of one factor as written: a number, a list, {from, to, step} or {from, to, levels}.
/// Ranges are from + i·step (to included within 1e-9 relative) and levels are evenly spaced from
/// `from` to `to`; every value is rounded to 1e-9. Throws InputError at `node` when malformed
/// (empty list, reversed range, step <= 0, levels < 1, unknown range field).
[[nodiscard]] std::vector<double> expand_values(const YamlNode& node);

}  // namespace emrm::core
