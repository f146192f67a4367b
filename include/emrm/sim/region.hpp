#pragma once

// A cell's verdict as names: its mitigability region and what backs it (docs/simulate.md,
// "What is simulated" and "Evidence"), each named once (core::EnumNames) for the store, the
// exports, JSON and messages.

#include <array>
#include <cstdint>
#include <string_view>
#include <utility>

#include "emrm/core/enum_names.hpp"

namespace emrm::sim {

/// Mitigability region of a cell (docs/simulate.md, "What is simulated"); named G, Y, O, R and
/// infeasible (core::EnumNames below).
enum class Region : std::uint8_t { kG, kY, kO, kR, kInfeasible };

/// What backs a claim (docs/simulate.md, "Evidence"): an executed trajectory that can be replayed
/// (an avoidance, or a fixed maneuver's own run), a proof that nothing avoids, or neither (a search
/// that found no avoidance, without proof that none exists).
enum class Evidence : std::uint8_t { kWitness, kCertificate, kUndecided };

/// What backs an O or R cell's split (docs/simulate.md): a found outcome below the reference's
/// level (witness, O); the reference already at the lowest contact level, L4 (proof, R); the
/// searches found nothing below the reference's level, which is not a proof that nothing is
/// (search, R). kNone for G, Y and infeasible cells (named "").
enum class MitigationEvidence : std::uint8_t { kNone, kWitness, kProof, kSearch };

}  // namespace emrm::sim

template <>
struct emrm::core::EnumNames<emrm::sim::Region> {
  static constexpr std::array kNames{
      std::pair{sim::Region::kG, std::string_view("G")}, std::pair{sim::Region::kY, std::string_view("Y")},
      std::pair{sim::Region::kO, std::string_view("O")}, std::pair{sim::Region::kR, std::string_view("R")},
      std::pair{sim::Region::kInfeasible, std::string_view("infeasible")}};
};
template <>
struct emrm::core::EnumNames<emrm::sim::Evidence> {
  static constexpr std::array kNames{std::pair{sim::Evidence::kWitness, std::string_view("witness")},
                                     std::pair{sim::Evidence::kCertificate, std::string_view("certificate")},
                                     std::pair{sim::Evidence::kUndecided, std::string_view("undecided")}};
};
template <>
struct emrm::core::EnumNames<emrm::sim::MitigationEvidence> {
  static constexpr std::array kNames{std::pair{sim::MitigationEvidence::kNone, std::string_view("")},
                                     std::pair{sim::MitigationEvidence::kWitness, std::string_view("witness")},
                                     std::pair{sim::MitigationEvidence::kProof, std::string_view("proof")},
                                     std::pair{sim::MitigationEvidence::kSearch, std::string_view("search")}};
};

namespace emrm::sim {

[[nodiscard]] constexpr std::string_view region_name(Region r) noexcept { return core::enum_name(r); }
[[nodiscard]] constexpr std::string_view evidence_name(Evidence e) noexcept { return core::enum_name(e); }

}  // namespace emrm::sim
