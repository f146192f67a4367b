#pragma once

// The T-junction's factors for tests that build cells and records by hand: its factor table with the
// default scene, and a record's named view.

#include "emrm/campaign/records.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::test {

/// The T-junction's factor table with the default scene.
inline const sim::FactorTable& tjunction_factors() {
  static const sim::FactorTable table = sim::scenario_factors(sim::SceneConfig{});
  return table;
}

/// A cell's factors by name.
inline sim::TJunctionCell named(const sim::CellInput& cell) { return sim::TJunctionCell::of(cell); }
/// A record's factors by name.
inline sim::TJunctionCell named(const campaign::CellRecord& r) { return sim::TJunctionCell::of(r.factors); }

}  // namespace emrm::test
