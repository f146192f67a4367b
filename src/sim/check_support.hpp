#pragma once

// What rollout.cpp, step.cpp, validity.cpp and termination.cpp share. Internal to src/sim; in a
// named namespace, so that the checks built from it may be members of the checkers' built-in
// structs (detail::ValidityChecks, detail::TerminationTests) in a unity batch too (docs/testing.md).

#include <limits>
#include <optional>

#include "emrm/core/geometry.hpp"
#include "emrm/core/trig.hpp"
#include "emrm/sim/step.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim::detail {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The velocity of the CG in the road frame.
inline core::Vec2 world_velocity(const VehicleState& s) {
  const auto [c, sn] = core::cos_sin(s.yaw_rad);
  return {s.vx_mps * c - s.vy_mps * sn, s.vx_mps * sn + s.vy_mps * c};
}

// The built-in checks answer through `why` and return whether the step ends the rollout: plain
// flags rather than std::optional<Termination>, whose piecewise stores and whole reads stalled the
// per-step loop on store forwarding (measured: ~6 % of a cheap cell).
inline bool end(Termination& why, Termination reason) noexcept {
  why = reason;
  return true;
}

// check() of a list of checks, from its ends().
template <class Checks>
std::optional<Termination> answer_of(const Checks& checks, Step& step, RolloutResult& result) {
  Termination why{};
  return checks.ends(step, result, why) ? std::optional<Termination>(why) : std::nullopt;
}

}  // namespace emrm::sim::detail
