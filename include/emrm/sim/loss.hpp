#pragma once

// Energy-based loss assessment (docs/physics.md, "Impacts and losses"): Δv of the ego from momentum conservation,
// injury and fatality risk curves, and the loss level of an outcome.

#include "emrm/core/geometry.hpp"
#include "emrm/sim/actor.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {

/// A rigid body at the moment of impact, in the road frame.
struct ImpactBody {
  double mass_kg = 0.0;
  double yaw_inertia_kgm2 = 0.0;
  core::Vec2 position_m;  ///< centre of mass
  core::Vec2 velocity_mps;
  double yaw_rate_radps = 0.0;
};

struct ImpactAssessment {
  double impact_speed_mps = 0.0;  ///< ego speed at contact
  double delta_v_mps = 0.0;       ///< ego's change of velocity through the impact
  double p_mais3 = 0.0;
  double p_fatal = 0.0;
  int loss_level = 0;  ///< 0, 4, 6 or 7
  /// Impulse the ego receives (N·s, road frame); the other body receives its opposite.
  core::Vec2 ego_impulse_ns;
};

/// Central impact: Δv = (1 + e) · m_other / (m_ego + m_other) · |v_rel,n|.
[[nodiscard]] double central_delta_v_mps(double ego_mass_kg, double other_mass_kg, double relative_normal_speed_mps,
                                         double restitution) noexcept;
/// P(MAIS3+) = 1 / (1 + exp(a − b·Δv)).
[[nodiscard]] double p_mais3(double delta_v_mps, const SeverityConfig& c) noexcept;
/// P(fatal) = min(1, (Δv / ref)^n).
[[nodiscard]] double p_fatal(double delta_v_mps, const SeverityConfig& c) noexcept;
/// A pedestrian's risk of death when struck at `impact_kph` (the closing speed, km/h):
/// 1 / (1 + exp(a − b·v)) with SeverityConfig's pedestrian_fatal_* (Hussain et al. 2019).
[[nodiscard]] double pedestrian_p_fatal(double impact_kph, const SeverityConfig& c) noexcept;
/// A pedestrian's risk of a serious injury (AIS 4+, which bounds MAIS3+ from below) when struck at
/// `impact_kph`: the pedestrian_serious_* logistic (fitted to Tefft 2013).
[[nodiscard]] double pedestrian_p_serious(double impact_kph, const SeverityConfig& c) noexcept;
/// A cyclist's risk of a serious injury (MAIS3+) when struck at `impact_kph`: the cyclist_serious_*
/// logistic (Lubbe, Wu & Jeppsson 2022, a 40-year-old rider).
[[nodiscard]] double cyclist_p_serious(double impact_kph, const SeverityConfig& c) noexcept;
/// Whether an actor of this kind is a vulnerable road user, harmed by the impact speed rather than by
/// the occupants' Δv: a pedestrian or a cyclist.
[[nodiscard]] bool vulnerable_road_user(ActorKind kind) noexcept;
/// The impact on the car's occupants (`occupants`, from assess_impact) with a vulnerable road user of
/// `kind` struck at `closing_speed_mps`: the risks are the worse of the occupants' and the road
/// user's (a cyclist's death risk is the pedestrian's), and the level is L7 when that P(fatal)
/// reaches l7_p_fatal, else L6 — a person struck is injured (docs/physics.md, "Pedestrians",
/// "Cyclists").
[[nodiscard]] ImpactAssessment with_road_user(ImpactAssessment occupants, ActorKind kind, double closing_speed_mps,
                                              const SeverityConfig& c) noexcept;

/// Whether a departure down an embankment of `slope_h` (horizontal run per unit of drop) rolls the
/// car over: it is steeper than the critical slope (SeverityConfig::critical_slope_h).
[[nodiscard]] bool rolls_over(double slope_h, const SeverityConfig& c) noexcept;
/// 0 without contact or departure; L4 on either; L6 when P(MAIS3+) ≥ its threshold; L7 when
/// P(fatal) ≥ its threshold.
[[nodiscard]] int loss_level(bool contact, bool road_departure, double p_mais3_value, double p_fatal_value,
                             const SeverityConfig& c) noexcept;

/// Impact of `ego` on `other` at `contact` (normal from ego towards other): the normal impulse
/// uses the effective mass including rotation, J_n = (1+e) m_eff v_rel,n; the tangential impulse
/// is limited by contact friction. Δv = |J| / m_ego. Separating bodies give Δv = 0 (loss level
/// L4: they touch). No contact gives an all-zero assessment. The ego's mass must be positive; a
/// non-positive mass or yaw inertia of `other` (or inertia of the ego) stands for an infinite one:
/// an immovable obstacle, or a body that does not turn.
[[nodiscard]] ImpactAssessment assess_impact(const ImpactBody& ego, const ImpactBody& other,
                                             const core::Contact& contact, const SeverityConfig& c) noexcept;

}  // namespace emrm::sim
