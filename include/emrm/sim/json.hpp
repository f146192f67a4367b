#pragma once

// The stable JSON form of a simulated cell (docs/simulate.md, "JSON"; listed in docs/outputs.md).

#include <nlohmann/json.hpp>

#include "emrm/sim/simulate.hpp"

namespace emrm::sim {

struct JsonOptions {
  bool timing = false;  ///< add planner wall-clock times (they vary run to run; off keeps output reproducible)
  bool paths = false;   ///< add the executed trajectory of every strategy
};

/// {"input":…, "feasible":…, "region":…, "unmitigated":…, "strategies":{name: …}}.
[[nodiscard]] nlohmann::json to_json(const CellResult& result, std::uint64_t seed, const JsonOptions& options = {});

}  // namespace emrm::sim
