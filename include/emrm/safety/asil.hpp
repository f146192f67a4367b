#pragma once

#include "emrm/safety/model.hpp"

namespace emrm::safety {

/// ASIL by ISO 26262-3 Table 4: with S1–S3, E1–E4 and C1–C3, the sum of the three indices
/// gives 10 → D, 9 → C, 8 → B, 7 → A, anything lower → QM. Any rating of 0 gives QM.
[[nodiscard]] Asil determine_asil(Severity s, Exposure e, Controllability c) noexcept;

/// The ASIL of a hazard's own S/E/C ratings.
[[nodiscard]] inline Asil determine_asil(const Hazard& h) noexcept {
  return determine_asil(h.severity, h.exposure, h.controllability);
}

/// The first rule of `table` whose stated ratings all equal the hazard's, or nullptr. A rule
/// that names a rating the hazard does not state does not match.
[[nodiscard]] const SmilRule* find_smil_rule(const SmilTable& table, const Hazard& h) noexcept;

}  // namespace emrm::safety
