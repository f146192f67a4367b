#include "emrm/sim/loss.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace emrm::sim {
namespace {

// 1/m and 1/I with "non-positive" standing for infinite (an immovable or non-rotating body).
double inverse(double value) noexcept { return value > 0.0 ? 1.0 / value : 0.0; }

// Velocity of the material point at `r` from the centre of mass: v + ω × r (ω along z).
core::Vec2 point_velocity(const ImpactBody& body, core::Vec2 r) noexcept {
  return body.velocity_mps + core::Vec2{-r.y, r.x} * body.yaw_rate_radps;
}

// 1 / (effective mass of the pair along `direction`) for impulses applied at r_a and r_b.
double inverse_effective_mass(const ImpactBody& a, const ImpactBody& b, core::Vec2 r_a, core::Vec2 r_b,
                              core::Vec2 direction) noexcept {
  const double arm_a = r_a.cross(direction);
  const double arm_b = r_b.cross(direction);
  return inverse(a.mass_kg) + inverse(b.mass_kg) + arm_a * arm_a * inverse(a.yaw_inertia_kgm2) +
         arm_b * arm_b * inverse(b.yaw_inertia_kgm2);
}

ImpactAssessment with_risks(ImpactAssessment out, const SeverityConfig& c) noexcept {
  out.p_mais3 = p_mais3(out.delta_v_mps, c);
  out.p_fatal = p_fatal(out.delta_v_mps, c);
  out.loss_level = loss_level(true, false, out.p_mais3, out.p_fatal, c);
  return out;
}

}  // namespace

double central_delta_v_mps(double ego_mass_kg, double other_mass_kg, double relative_normal_speed_mps,
                           double restitution) noexcept {
  return (1.0 + restitution) * other_mass_kg / (ego_mass_kg + other_mass_kg) * std::abs(relative_normal_speed_mps);
}

double p_mais3(double delta_v_mps, const SeverityConfig& c) noexcept {
  return 1.0 / (1.0 + std::exp(c.mais3_intercept - c.mais3_slope_per_mps * delta_v_mps));
}

double p_fatal(double delta_v_mps, const SeverityConfig& c) noexcept {
  if (!(delta_v_mps > 0.0)) return 0.0;
  return std::min(1.0, std::pow(delta_v_mps / c.fatal_reference_mps, c.fatal_exponent));
}

double pedestrian_p_fatal(double impact_kph, const SeverityConfig& c) noexcept {
  return 1.0 / (1.0 + std::exp(c.pedestrian_fatal_intercept - c.pedestrian_fatal_slope_per_kph * impact_kph));
}

double pedestrian_p_serious(double impact_kph, const SeverityConfig& c) noexcept {
  return 1.0 / (1.0 + std::exp(c.pedestrian_serious_intercept - c.pedestrian_serious_slope_per_kph * impact_kph));
}

double cyclist_p_serious(double impact_kph, const SeverityConfig& c) noexcept {
  return 1.0 / (1.0 + std::exp(c.cyclist_serious_intercept - c.cyclist_serious_slope_per_kph * impact_kph));
}

bool vulnerable_road_user(ActorKind kind) noexcept {
  return kind == ActorKind::kPedestrian || kind == ActorKind::kCyclist;
}

ImpactAssessment with_road_user(ImpactAssessment occupants, ActorKind kind, double closing_speed_mps,
                                const SeverityConfig& c) noexcept {
  const double kph = std::abs(closing_speed_mps) * 3.6;
  occupants.p_fatal = std::max(occupants.p_fatal, pedestrian_p_fatal(kph, c));
  occupants.p_mais3 = std::max(occupants.p_mais3,
                               kind == ActorKind::kCyclist ? cyclist_p_serious(kph, c) : pedestrian_p_serious(kph, c));
  occupants.loss_level = occupants.p_fatal >= c.l7_p_fatal ? 7 : 6;
  return occupants;
}

bool rolls_over(double slope_h, const SeverityConfig& c) noexcept { return slope_h < c.critical_slope_h; }

int loss_level(bool contact, bool road_departure, double p_mais3_value, double p_fatal_value,
               const SeverityConfig& c) noexcept {
  if (!contact && !road_departure) return 0;
  if (p_fatal_value >= c.l7_p_fatal) return 7;
  if (p_mais3_value >= c.l6_p_mais3) return 6;
  return 4;
}

ImpactAssessment assess_impact(const ImpactBody& ego, const ImpactBody& other, const core::Contact& contact,
                               const SeverityConfig& c) noexcept {
  assert(ego.mass_kg > 0.0);
  if (!contact.touching) return {};

  const core::Vec2 n = contact.normal;
  const core::Vec2 t{-n.y, n.x};
  const core::Vec2 r_ego = contact.point - ego.position_m;
  const core::Vec2 r_other = contact.point - other.position_m;
  const core::Vec2 v_rel = point_velocity(ego, r_ego) - point_velocity(other, r_other);
  const double v_rel_n = v_rel.dot(n);  // > 0: the ego closes on `other`

  ImpactAssessment out;
  out.impact_speed_mps = ego.velocity_mps.norm();
  if (v_rel_n > 0.0) {
    const double normal_impulse =
        (1.0 + c.restitution) * v_rel_n / inverse_effective_mass(ego, other, r_ego, r_other, n);
    // Friction opposes the sliding, but cannot do more than stop it (sticking).
    const double v_rel_t = v_rel.dot(t);
    const double sticking_impulse = std::abs(v_rel_t) / inverse_effective_mass(ego, other, r_ego, r_other, t);
    const double tangential_impulse = std::min(c.contact_friction * normal_impulse, sticking_impulse);
    const double slide_sign = v_rel_t > 0.0 ? 1.0 : (v_rel_t < 0.0 ? -1.0 : 0.0);
    out.ego_impulse_ns = -(n * normal_impulse + t * (tangential_impulse * slide_sign));
    out.delta_v_mps = out.ego_impulse_ns.norm() / ego.mass_kg;
  }
  return with_risks(out, c);
}

}  // namespace emrm::sim
