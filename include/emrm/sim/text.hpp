#pragma once

// The printed form of a simulated cell, as `emrm simulate` shows it without --json (the JSON form
// is sim/json.hpp; both are described in docs/outputs.md).

#include <cstdint>
#include <string>

#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::sim {

/// The cell's inputs and initial distance; for a feasible cell its region, the unmitigated impact,
/// one Markdown table row per strategy and the EMRM FSM traces; for an infeasible one why.
/// `config` supplies max_initial_distance_m; `seed` is the seed the cell was simulated with.
[[nodiscard]] std::string to_text(const CellResult& result, const SceneConfig& config, std::uint64_t seed);

}  // namespace emrm::sim
