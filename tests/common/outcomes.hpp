#pragma once

// A cell's outcome of one strategy, by its name, for tests that read a CellResult.

#include <stdexcept>
#include <string>
#include <string_view>

#include "emrm/sim/simulate.hpp"

namespace emrm::test {

/// The outcome of `strategy` in `r`; throws std::logic_error when the cell has none.
inline const sim::StrategyOutcome& outcome(const sim::CellResult& r, std::string_view strategy) {
  for (const auto& o : r.strategies)
    if (o.strategy == strategy) return o;
  throw std::logic_error("no outcome of " + std::string(strategy));
}

}  // namespace emrm::test
