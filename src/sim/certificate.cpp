// Unavoidability certificates: a sound bound on the reach of the single-track Fiala model in a
// cell (docs/physics.md, "Unavoidability certificates", numbers every inequality used here as
// (C1)…(C12), with lettered additions such as (C2b) or (C10a)). The layout:
// - the relaxation (C1–C4): coasting straight during the latency, then |a_CG| ≤ mu·g, speed ≤ v0,
//   and the event "the CG first reaches x = xi" that every avoiding trajectory passes through;
// - the comparison system (C5–C8): nondecreasing upper bounds, over time after the latency, on the
//   front wheel's and both axles' lateral slip velocities, the yaw rate and the heading, and from
//   them caps on the axle forces' body-lateral components (Fiala envelopes of the slip bounds);
// - the duality bound (C9–C10): lateral displacements (of the CG, of the axle points) and the yaw
//   angle at an arrival time T are double integrals of the axle forces; the arrival constraint
//   (the braking it takes to reach xi at T) enters with a multiplier lambda ≥ 0, so for every
//   lambda the pointwise maximum is an upper bound (weak duality);
// - the witnesses (C11–C12): the geometry that turns those bounds into a contact or a departure.

#include "emrm/sim/certificate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

#include "certificate_bounds.hpp"
#include "emrm/sim/family.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {
namespace {

using namespace certificate_bounds;  // the bounds are this file's vocabulary

// The bound is stated for the continuous model; integrating it with a coarser step than this is
// not covered by the margin (docs/physics.md).
constexpr double kMaxSceneStep_s = 0.02;
constexpr double kStep_s = 0.00125;  // certify_unavoidable's integration step (check_certificate: also half)
// Multipliers of the arrival constraint (dimensionless for displacements: braking and lateral
// accelerations trade one for one). Any lambda ≥ 0 gives a valid bound; the checker adds more.
constexpr std::array kLambdas{0.0, 0.1, 0.2, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0, 3.0, 5.0, 10.0};
// Heading caps tried by the "side" witness: 0.02 rad apart up to 1.3 rad (a cap just above the
// heading bound at the crossing is the one that shows most).
constexpr int kHeadingCaps = 65;
constexpr double kHeadingCapStep_rad = 0.02;
// Where between the front corners' crossing (0) and the rear corners' (1) the "flank" witnesses
// put the CG.
constexpr std::array kFlankParts{0.5, 0.75, 1.0};

// (C11) disc, (C12) side: the cross-section at the truck's near side, (C12a) flank: at its far side.
enum class WitnessKind { kDisc, kSide, kFlank };
constexpr std::array kWitnessNames{"disc", "side", "flank"};

struct Witness {
  WitnessKind kind = WitnessKind::kDisc;
  double crossing_x = 0.0;
  double heading_cap = 0.0;
};

// The line x = x_c whose cross-section a side or flank witness shows in the truck: inside the
// truck's x-range by the margin, at its near side or its far side.
double section_x(const Setup& c, WitnessKind kind) {
  return kind == WitnessKind::kFlank ? c.near_x + c.truck_width - kCertificateMinMargin_m
                                     : c.near_x + kCertificateMinMargin_m;
}

struct Evaluation {
  double margin = -kInf;
  double window_start_s = 0.0, window_end_s = 0.0;
};

// The arrival window of the CG at x = xi, as times after the latency (C3): no faster than v0, no
// later than the least progress of (C2a).
std::pair<double, double> arrival_window(const Setup& c, const Braking& braking, double xi) {
  const double travel = xi - c.x_tau;
  return {travel / c.v0, braking.latest(travel)};
}

// (C11–C12) The margin by which a car whose cross-section at the crossing line spans at least
// [bottom_hi, top_lo] (and is at least `width` long), crossing it between the absolute times
// t_start and t_end, overlaps the truck or crosses an edge: the larger of the two ways each route
// fails, the smaller over the two routes (below the truck's front, above its far end).
double route_margins(const Setup& c, double top_lo, double bottom_hi, double t_start, double t_end) {
  const double front_start = c.scene->truck_front_y_at(t_start);
  const double front_end = c.scene->truck_front_y_at(t_end);
  // Below the truck: the car's cross-section (at least `width` across) must fit between the right
  // edge and the truck's front, which only descends: its highest point is below the front at
  // the start of the interval at the latest.
  const double below = std::max(top_lo - front_start, 0.5 * (c.width - (front_start - c.y_min)));
  // Above the truck (behind it, once it has crossed): the front only descends, so the truck's far
  // end is lowest at the end of the interval.
  const double rear_end = front_end + c.truck_length;
  const double above = std::max(rear_end - bottom_hi, 0.5 * (c.width - (c.y_max - rear_end)));
  return std::min(below, above);
}

Evaluation evaluate(const Setup& c, Bounder& b, const Braking& braking, const Witness& w) {
  Evaluation out;
  const double xi = w.crossing_x;
  const double min_margin = kCertificateMinMargin_m;
  const bool disc = w.kind == WitnessKind::kDisc;
  const double face_x = section_x(c, w.kind);  // the cross-section's line, inside the truck by the margin
  if (!(xi < c.x_tau + braking.stop_travel()) || !(xi > c.x0)) return out;

  // Geometry of the witness.
  double a_lo = 0.0, a_hi = 0.0, cos_cap = 1.0, sin_cap = 0.0;
  if (disc) {
    if (c.cf < 0.5 * c.width || c.cr < 0.5 * c.width) return out;  // the disc must lie in the car
    if (xi < c.near_x + min_margin || xi > c.near_x + c.truck_width - min_margin) return out;
  } else {
    if (!(w.heading_cap > 0.0 && w.heading_cap < 1.5)) return out;
    sin_cap = std::sin(w.heading_cap);
    cos_cap = std::cos(w.heading_cap);
    const double gap = face_x - xi;
    // Both sides of the car cross x = face_x for every heading within the cap (front corners past
    // it, rear corners short of it), at body coordinates a in [a_lo, a_hi], monotone in ψ.
    if (xi < face_x - (c.cf * cos_cap - 0.5 * c.width * sin_cap)) return out;
    if (xi > face_x + (c.cr * cos_cap - 0.5 * c.width * sin_cap)) return out;
    if (std::abs(gap) * sin_cap >= 0.5 * c.width) return out;
    a_lo = (gap - 0.5 * c.width * sin_cap) / cos_cap;
    a_hi = (gap + 0.5 * c.width * sin_cap) / cos_cap;
  }

  // Which points' displacement matters, and how it follows from the functionals (C12).
  const auto side_displacement = [&](double cg, double front, double rear) {
    // |ΔY_a| for the body point at a, by four sound routes; the largest over the a-range (each
    // route is convex in a) of each route, the least over routes.
    const auto route = [&](auto&& at) { return std::max(at(a_lo), at(a_hi)); };
    const double l = c.wheelbase;
    const double by_axles =
        route([&](double a) { return std::abs(a + c.lr) / l * front + std::abs(c.lf - a) / l * rear; });
    const double by_cg = route([&](double a) { return cg + std::abs(a) * sin_cap; });
    const double by_front = route([&](double a) { return front + std::abs(a - c.lf) * sin_cap; });
    const double by_rear = route([&](double a) { return rear + std::abs(a + c.lr) * sin_cap; });
    return std::min({by_axles, by_cg, by_front, by_rear});
  };

  double margin = kInf;
  if (xi <= c.x_tau) {
    // Reached during the latency: exactly on the straight line, at a known time.
    const double t = (xi - c.x0) / c.v0;
    margin = route_margins(c, c.y0 + 0.5 * c.width, c.y0 - 0.5 * c.width, t, t);
    out.window_start_s = out.window_end_s = t;
  } else {
    const auto [early, computed_late] = arrival_window(c, braking, xi);
    // Braking can only make the car arrive later, but the latest arrival is found on the bound's
    // time grid: where the car gets there before its brakes act, it can come out a fraction of a
    // step before the earliest, and the window would hold no step at all (a margin shown for no
    // arrival time). Then the car arrives at its constant speed, exactly at the earliest time.
    const double late = std::max(early, computed_late);
    out.window_start_s = c.tau + early;
    out.window_end_s = c.tau + late;
    const int k_last = b.index_at_or_after(late);
    if (k_last < 0) return out;
    int k = std::max(1, b.index_at_or_after(early));
    for (; k <= k_last; ++k) {
      const double s_lo = b.time(k - 1);
      const double s_hi = b.time(k);
      // Braking impulse moment needed to arrive at s: ∫(s − σ) b dσ = x_τ + v0 s − xi.
      const double need_lo = c.x_tau + c.v0 * s_lo - xi;
      const double need_hi = c.x_tau + c.v0 * s_hi - xi;
      const double d_cg = b.bound(Functional::kCg, k, need_lo, need_hi);
      double top_lo = 0.0, bottom_hi = 0.0;
      if (disc) {
        top_lo = c.y0 - d_cg + 0.5 * c.width;
        bottom_hi = c.y0 + d_cg - 0.5 * c.width;
      } else {
        const double psi = std::min(b.bound(Functional::kYaw, k, need_lo, need_hi), b.heading(k));
        if (!(psi < w.heading_cap)) return out;
        const double d_front = b.bound(Functional::kFrontAxle, k, need_lo, need_hi);
        const double d_rear = b.bound(Functional::kRearAxle, k, need_lo, need_hi);
        const double disp = side_displacement(d_cg, d_front, d_rear);
        top_lo = c.y0 - disp + 0.5 * c.width * cos_cap;
        bottom_hi = c.y0 + disp - 0.5 * c.width * cos_cap;
      }
      margin = std::min(margin, route_margins(c, top_lo, bottom_hi, c.tau + s_lo, c.tau + s_hi));
      if (!(margin >= min_margin)) return out;
    }
  }
  out.margin = margin;
  return out;
}

std::vector<Witness> witnesses(const Setup& c) {
  std::vector<Witness> out;
  const double face_x = c.near_x + kCertificateMinMargin_m;
  for (double xi : {face_x, face_x + 0.1, face_x + 0.3, c.near_x + 0.5 * c.truck_width,
                    c.near_x + c.truck_width - kCertificateMinMargin_m})
    out.push_back({WitnessKind::kDisc, xi, 0.0});
  // Where the CG is when the car's front corners have just crossed the line x_c (part 0) or its
  // rear corners are about to (part 1, less a millimetre), the car's heading within the cap.
  const auto straddling = [&](double x_c, double cap, double part) {
    const double front_in = x_c - (c.cf * std::cos(cap) - 0.5 * c.width * std::sin(cap));
    const double rear_out = x_c + (c.cr * std::cos(cap) - 0.5 * c.width * std::sin(cap)) - 0.001;
    return front_in + part * (rear_out - front_in);
  };
  for (int i = 1; i <= kHeadingCaps; ++i) {
    const double cap = kHeadingCapStep_rad * i;
    out.push_back({WitnessKind::kSide, straddling(face_x, cap, 0.0), cap});
  }
  // The flank, tried after every other witness: a truck still entering the car's path as the car
  // crossed its near side comes down onto the car's side while the car is still in its x-range.
  // The cross-section at its far side, the CG half, three quarters and all of the way to the rear
  // corners' crossing (evaluate() turns down the caps at which the car cannot straddle the line).
  // Only where the truck still moves as the car's front reaches its near side (at t = TTC at the
  // earliest): a truck at rest by then is in the same place when the car crosses its far side, and
  // the car has had longer to move aside.
  const core::Vec2 truck_velocity = c.scene->hazard_at(c.scene->ttc_s()).velocity_mps;
  if (truck_velocity.x == 0.0 && truck_velocity.y == 0.0) return out;
  const double far_x = section_x(c, WitnessKind::kFlank);
  for (const double part : kFlankParts)
    for (int i = 1; i <= kHeadingCaps; ++i) {
      const double cap = kHeadingCapStep_rad * i;
      out.push_back({WitnessKind::kFlank, straddling(far_x, cap, part), cap});
    }
  return out;
}

bool same_actuation(const ActuationConfig& a, const ActuationConfig& b) {
  return a.perception_latency_s == b.perception_latency_s && a.brake_dead_time_s == b.brake_dead_time_s &&
         a.brake_ramp_s == b.brake_ramp_s && a.max_decel_mps2 == b.max_decel_mps2 &&
         a.steer_dead_time_s == b.steer_dead_time_s && a.steer_time_constant_s == b.steer_time_constant_s;
}

bool applicable(const Scene& scene) {
  return !no_certificate_bound(scene.config()) && scene.initial_speed_mps() > 0.0 && scene.friction() > 0.0;
}

}  // namespace

std::optional<std::string> no_certificate_bound(const SceneConfig& config) {
  if (!has_tjunction_analytics(config))
    return fmt::format("scenario family '{}' has no certificate bound: no cell is certified unavoidable",
                       config.family);
  const auto model = find_vehicle_model(config.simulation.vehicle_model);
  if (!model || !model->certificate_bound)
    return fmt::format("vehicle model '{}' has no certificate bound: no cell is certified unavoidable",
                       config.simulation.vehicle_model);
  if (config.simulation.dt_s > kMaxSceneStep_s)
    return fmt::format(
        "a time step of {:g} s is above the certificate bound's {:g} s: no cell is certified unavoidable",
        config.simulation.dt_s, kMaxSceneStep_s);
  return std::nullopt;
}

std::optional<Certificate> certify_unavoidable(const Scene& scene) {
  if (!applicable(scene)) return std::nullopt;
  const Setup c = make_setup(scene);
  Bounder bounder(c, kStep_s, std::vector<double>(kLambdas.begin(), kLambdas.end()));
  const Braking braking(c, bounder);
  const double stop_reach = c.x_tau + braking.stop_travel();
  // Quick exit: if the CG can stop before any witness's crossing, nothing can be shown.
  const std::vector<Witness> ws = witnesses(c);
  if (std::none_of(ws.begin(), ws.end(), [&](const Witness& w) { return w.crossing_x < stop_reach; }))
    return std::nullopt;
  for (const Witness& w : ws) {
    const Evaluation e = evaluate(c, bounder, braking, w);
    if (!(e.margin >= kCertificateMinMargin_m)) continue;
    Certificate cert;
    cert.margin_m = e.margin;
    cert.witness = kWitnessNames[static_cast<std::size_t>(w.kind)];
    cert.crossing_x_m = w.crossing_x;
    cert.heading_cap_rad = w.heading_cap;
    cert.window_start_s = e.window_start_s;
    cert.window_end_s = e.window_end_s;
    cert.stop_reach_x_m = stop_reach;
    cert.step_s = kStep_s;
    cert.cell = scene.cell();
    cert.latency_s = scene.config().actuation.perception_latency_s;
    cert.actuation = scene.config().actuation;
    return cert;
  }
  return std::nullopt;
}

bool check_certificate(const Scene& scene, const Certificate& cert) {
  if (cert.method != "lateral-reach" || !applicable(scene)) return false;
  const CellInput& a = cert.cell;
  const CellInput& b = scene.cell();
  if (a != b || cert.latency_s != scene.config().actuation.perception_latency_s ||
      !same_actuation(cert.actuation, scene.config().actuation))
    return false;
  const auto* named = std::find(kWitnessNames.begin(), kWitnessNames.end(), cert.witness);
  if (named == kWitnessNames.end()) return false;
  if (!std::isfinite(cert.crossing_x_m) || !std::isfinite(cert.heading_cap_rad)) return false;
  const Setup c = make_setup(scene);
  const Witness w{static_cast<WitnessKind>(named - kWitnessNames.begin()), cert.crossing_x_m, cert.heading_cap_rad};
  // A denser set of multipliers (the certifier's among them): every one of them is a valid bound on
  // its own. The certifier's step is tried first, then half of it (each is a sound bound).
  std::vector<double> lambdas(kLambdas.begin(), kLambdas.end());
  for (int i = 1; i <= 240; ++i) lambdas.push_back(0.05 * i);
  for (const double step : {kStep_s, 0.5 * kStep_s}) {
    Bounder bounder(c, step, lambdas);
    const Braking braking(c, bounder);
    if (evaluate(c, bounder, braking, w).margin >= kCertificateMinMargin_m) return true;
  }
  return false;
}

}  // namespace emrm::sim
