#pragma once

// The safety-case analysis as `emrm analyze` runs it, shared by the commands that check a case
// before they use it (`emrm plan`, `emrm reproduce`).

#include <filesystem>
#include <optional>

#include "emrm/safety/analysis.hpp"

namespace emrm::workflow {

/// Loads the safety case `file` and analyzes it, its UCAs' transitions checked against `fsm_file`
/// when given, else against the case's own `fsm:` entry (neither with `no_fsm`). Throws InputError
/// for a bad safety case or FSM file.
[[nodiscard]] safety::Analysis analyze_safety_file(const std::filesystem::path& file,
                                                   const std::optional<std::filesystem::path>& fsm_file = std::nullopt,
                                                   bool no_fsm = false);

}  // namespace emrm::workflow
