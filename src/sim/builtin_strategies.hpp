#pragma once

// The strategies emrm ships with (private to sim: the registry starts from them).

#include <vector>

#include "emrm/sim/strategy.hpp"

namespace emrm::sim {

/// Emergency stop, dodge, drift to avoid, drift to accident, EMRM and the oracle (best_strategy), in
/// evaluation order.
[[nodiscard]] std::vector<RegisteredStrategy> builtin_strategies();

}  // namespace emrm::sim
