#pragma once

// The played trajectories as CSV, to compare with esmini's recording of the same scenario
// (docs/import.md, "Trace"): header `t,actor,x,y,heading,speed`, one row per entity and sample,
// ordered by t then actor; numbers with 17 significant digits (they read back to the same double).

#include <istream>
#include <ostream>
#include <string>

#include "emrm/openscenario/player.hpp"

namespace emrm::openscenario {

void write_trace_csv(std::ostream& out, const Trajectories& trajectories);

/// Reads what write_trace_csv writes. Throws InputError at `file`'s line and column for another
/// header, a row without six fields or a field that is not a number.
[[nodiscard]] Trajectories read_trace_csv(std::istream& in, const std::string& file);

}  // namespace emrm::openscenario
