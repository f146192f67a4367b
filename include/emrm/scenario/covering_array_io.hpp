#pragma once

// The printed form of a covering array: the CSV `emrm ca` writes to standard output (schema:
// docs/outputs.md, docs/covering-arrays.md).

#include <string>

#include "emrm/scenario/covering_array.hpp"
#include "emrm/scenario/pict_model.hpp"

namespace emrm::scenario {

/// The array as CSV: a header naming the factors, then one line per row. With a `model` (borrowed,
/// may be null) the header is its parameter names and each entry the value as written in the
/// model; without, the header is p1, p2, … and each entry the 0-based level index. A model must
/// have one parameter per factor of `ca` (asserted).
[[nodiscard]] std::string covering_array_csv(const CoveringArray& ca, const PictModel* model = nullptr);

}  // namespace emrm::scenario
