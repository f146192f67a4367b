#pragma once

// The unavoidability certificate's bounds (docs/physics.md, "Unavoidability certificates"): the
// cell's constants (C1–C4), the comparison system of slip, yaw and heading bounds (C5–C8), the
// duality tables of the displacement functionals (C9–C10) and the least x-progress (C2a). Internal
// to src/sim: certificate.cpp is the only user, and the witnesses (C11–C12) are there.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "certificate_support.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/termination.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim::certificate_bounds {

using certificate_support::axle_pair_support;
using certificate_support::AxleSupport;
using certificate_support::fiala_cap;

constexpr double kInf = std::numeric_limits<double>::infinity();
// Longest time after the latency the bound is integrated; witnesses needing more are not tried.
constexpr double kHorizon_s = 3.0;
// The slip bounds need the body's forward speed (and the front wheel's rolling speed) bounded away
// from zero; below this the bound falls back to the plain friction limits.
constexpr double kMinRollingSpeed_mps = 0.1;

// Everything fixed for a cell.
struct Setup {
  // car
  double m, iz, lf, lr, wheelbase, h, width, cf, cr, rho, delta_max;
  // steering actuator (C1a): dead time, lag, and the simulator's step the wheel path is sampled at
  double steer_dead, steer_lag, steer_lead;
  double brake_dead;  // (C2a) no braking force until this long after the latency (one step's lead taken off)
  // (C2b) the brake level's ramp: it starts rising at brake_ramp_start (the dead time less one
  // step's lead, may be negative), at 1/brake_ramp per second (0: at once); the cap's share of mu·g
  double brake_ramp_start, brake_ramp, brake_scale;
  double a_f, a_r, kappa;   // 1/m + lf²/Iz, 1/m + lr²/Iz, |1/m − lf·lr/Iz|
  double slope_f, slope_r;  // Fiala slopes with the locked/ABS envelopes folded in (C5)
  // cell
  double mu, g, v0, tau, x0, x_tau, y0, stop_speed;
  double near_x, truck_width, truck_length, y_min, y_max;
  // grips: forward rolling (C4) and in general
  double grip_f_fwd, grip_r_fwd, grip_any, total_grip;
  // (C7a) the front's restoring force: its least grip rolling forwards, and its cornering stiffness
  double grip_f_min, stiffness_f;
  bool monotone_loads;  // (C4) the load formula is monotone in the commanded braking
  const Scene* scene;
};

// One grid point of the comparison system (C6–C8), at s = k·h after the latency.
struct Bound {
  double cap_f = 0.0, cap_r = 0.0;    // |q_f|, |q_r| ≤ (body-lateral components of the axle forces)
  double grip_f = 0.0, grip_r = 0.0;  // |F_f| ≤ grip_f, |F_r| ≤ grip_r
  double sin_psi = 0.0;               // |sin ψ| ≤
  double yaw_rate = 0.0;              // |r| ≤
};

struct Slip {        // comparison state: nondecreasing upper bounds
  double gf = 0.0;   // |v_f| front axle's body-lateral velocity
  double gr = 0.0;   // |v_r| rear axle's
  double gw = 0.0;   // |w_f| front wheel's lateral velocity in its own frame
  double r = 0.0;    // |r|
  double psi = 0.0;  // |ψ|
  double dv = 0.0;   // v0 − ẋ: the CG's lost x-velocity (C7b)
};

struct Rates {
  Slip d;
  Bound b;
  double spin_rate = 0.0;  // (C8a) v0 tan Δ / L: from this |r| on the axles cannot both turn the car
  double yaw_spin = 0.0;   // (C8a) the yaw acceleration bound once |r| ≥ spin_rate
  bool valid = true;
};

inline Setup make_setup(const Scene& scene) {
  const SceneConfig& c = scene.config();
  const VehicleParams& p = c.ego;
  Setup s{};
  s.scene = &scene;
  s.m = p.mass_kg;
  s.iz = p.yaw_inertia_kgm2;
  s.lf = p.cg_to_front_axle_m;
  s.lr = p.cg_to_rear_axle_m;
  s.wheelbase = p.wheelbase_m();
  s.h = p.cg_height_m;
  s.width = p.width_m;
  s.cf = p.cg_to_front_m();
  s.cr = p.cg_to_rear_m();
  s.rho = p.max_steer_rate_radps;
  s.delta_max = p.max_steer_rad;
  const ActuationConfig& act = c.actuation;
  s.steer_dead = act.steer_dead_time_s;
  s.steer_lag = act.steer_time_constant_s;
  // With actuators the simulator moves the wheels linearly between its steps' ends, where they sit
  // on the lagged response: one step's lead covers the chord (docs/physics.md, (C1a)).
  s.steer_lead = act.instant() ? 0.0 : c.simulation.dt_s;
  s.brake_dead = std::max(0.0, act.brake_dead_time_s - s.steer_lead);
  s.brake_ramp_start = act.brake_dead_time_s - s.steer_lead;
  s.brake_ramp = act.brake_ramp_s;
  s.a_f = 1.0 / s.m + s.lf * s.lf / s.iz;
  s.a_r = 1.0 / s.m + s.lr * s.lr / s.iz;
  s.kappa = std::abs(1.0 / s.m - s.lf * s.lr / s.iz);
  s.mu = scene.friction();
  s.g = kGravity_mps2;
  s.brake_scale = std::min(1.0, act.full_decel_mps2(s.mu) / (s.mu * s.g));
  s.total_grip = s.mu * s.m * s.g;
  // (C4) Loads. With the body moving forward (u > 0, front wheel rolling forwards) every commanded
  // per-load braking is in [−mu, 0]; while mu·h < lf and mu·h < 3L/4 the load formula's
  // acceleration is increasing in both, so it lies in [−mu·g, 0]: Fzf ≤ m g (lr + mu h)/L and
  // Fzr ≤ m g lf / L. Otherwise only the clamp [0, m g] is used.
  const bool monotone = s.mu * s.h < s.lf && s.mu * s.h < 0.75 * s.wheelbase;
  s.monotone_loads = monotone;
  s.grip_any = s.total_grip;
  s.grip_f_fwd = monotone ? std::min(1.0, (s.lr + s.mu * s.h) / s.wheelbase) * s.total_grip : s.total_grip;
  s.grip_r_fwd = monotone ? s.lf / s.wheelbase * s.total_grip : s.total_grip;
  // (C7a) With the same loads F_zf ≥ m g lr / L (the acceleration is at most 0); otherwise nothing.
  s.grip_f_min = monotone ? s.lr / s.wheelbase * s.total_grip : 0.0;
  s.stiffness_f = p.front_cornering_stiffness_n_per_rad;
  // (C5) A locked axle (mu Fz sin alpha) and the ABS floor (min(mu Fz, C tan alpha / 3)) stay under
  // the Fiala envelope of slope K as long as K ≥ 3 mu Fz.
  s.slope_f = std::max(p.front_cornering_stiffness_n_per_rad, 3.0 * s.total_grip);
  s.slope_r = std::max(p.rear_cornering_stiffness_n_per_rad, 3.0 * s.total_grip);

  s.v0 = scene.initial_speed_mps();
  s.tau = c.actuation.perception_latency_s;
  const VehicleState start = scene.ego_initial();
  s.x0 = start.x_m;
  s.y0 = start.y_m;
  s.x_tau = s.x0 + s.v0 * s.tau;
  // (C2) Before its speed can fall below the stop threshold (and below the kinematic blend) the
  // CG's x-velocity must fall from v0 to it at no more than mu·g (and less before the brakes act,
  // (C2a), class Braking): the CG travels at least so far.
  s.stop_speed = std::max(p.kinematic_blend_speed_mps, kStoppedSpeed_mps);
  s.near_x = scene.initial_distance_m();
  s.truck_width = c.truck.width_m;
  s.truck_length = c.truck.length_m;
  s.y_min = c.road.drivable_min_y_m();
  s.y_max = c.road.drivable_max_y_m();
  return s;
}

// (C1a) Bounds on the road-wheel angle and its rate at time s after the perception latency: the
// commanded angle moves at most at rho from zero; the wheels follow it after the dead time through
// a first-order lag, whose response to that ramp is R(t) = rho·(t − T(1 − e^(−t/T))) at rate
// rho·(1 − e^(−t/T)) (the lag's kernel is positive and integrates to one, so it keeps both bounds).
// (C1b) The simulator puts the wheels on the lagged response at its step ends and moves them
// linearly between: their angle is at most the chord of R, which is at most R one step ahead (R
// nondecreasing) and at most R + h²·rho/(8T) (R is convex and C¹, R'' ≤ rho/T: the chord of a
// convex function exceeds it by at most h²·max R''/8), or R + h·rho/4 without a lag (the chord
// across the kink at t = 0). The rate keeps the step's lead.
struct Wheel {
  double angle, rate;
};
inline double ramp_response(const Setup& c, double t) {
  if (t <= 0.0) return 0.0;
  if (c.steer_lag == 0.0) return c.rho * t;
  return c.rho * (t - c.steer_lag * (1.0 - std::exp(-t / c.steer_lag)));
}
inline Wheel wheel_bound(const Setup& c, double s) {
  const double t = s - c.steer_dead + c.steer_lead;
  if (t <= 0.0) return {0.0, 0.0};
  const double h = c.steer_lead;
  const double chord_excess = c.steer_lag > 0.0 ? h * h * c.rho / (8.0 * c.steer_lag) : 0.25 * h * c.rho;
  const double angle = std::min({c.delta_max, ramp_response(c, t), ramp_response(c, t - h) + chord_excess});
  const double rate = c.steer_lag == 0.0 ? c.rho : c.rho * (1.0 - std::exp(-t / c.steer_lag));
  return {angle, rate};
}

// (C2b) The applied brake level at s after the latency is at most (s − t_b + h)/t_r (a step's mean
// of a level rising at 1/t_r from the dead time), times the cap's share of mu·g.
inline double brake_level(const Setup& c, double s) {
  if (s <= c.brake_ramp_start) return 0.0;
  if (c.brake_ramp <= 0.0) return c.brake_scale;
  return std::min(1.0, (s - c.brake_ramp_start) / c.brake_ramp) * c.brake_scale;
}

// (C4a) The front's grip at s after the latency, rolling forwards. The load formula's acceleration is
// increasing in both commanded per-load brakings (C4), the front's at least −mu·ℓ (ℓ the brake
// level, (C2b)) and the rear's at least −mu (locked); its ABS pass brakes with |F_xf| ≤ ℓ·mu·F_zf
// and |F_xr| ≤ mu·F_zr, F_zf ≥ m g lr/L: so |a| ≤ mu·g·(lf + ℓ·lr)/L and
// F_zf ≤ m (g lr + |a| h)/L. Before the brakes act (no brake, no lock) a = 0.
inline double front_grip(const Setup& c, double s) {
  if (!c.monotone_loads) return c.grip_f_fwd;
  const double decel = s <= c.brake_dead ? 0.0 : c.mu * c.g * (c.lf + brake_level(c, s) * c.lr) / c.wheelbase;
  return std::min(c.grip_f_fwd, c.mu * c.m * (c.g * c.lr + decel * c.h) / c.wheelbase);
}

// (C2a–C2b) The CG's x-deceleration |ẍ| at s after the latency, for the wheel angle's and the
// bounds' values `sin_delta` and `b` there: the front's lateral force through the wheel angle and
// the lateral forces through the heading, plus, once the brakes act, the ramped front and the
// (possibly locked) rear; at most mu·g.
inline double decel_bound(const Setup& c, double s, double sin_delta, const Bound& b) {
  const double full = c.mu * c.g;
  double d = full * (sin_delta + b.sin_psi);
  if (s > c.brake_dead) d += (brake_level(c, s) * b.grip_f + b.grip_r) / c.m;
  return std::min(full, d);
}

// (C6–C8) The comparison system's rates at time s after the latency, for bounds `z`. `start`, when
// given, is the bound at the start of the step the rates are for: the front's restoring force (C7a)
// is taken at it (the least |w_f| bound on the step, so the least restoring force).
inline Rates rates_at(const Setup& c, double s, const Slip& z, bool was_valid, const Slip* start = nullptr) {
  Rates out;
  const Wheel wheel = wheel_bound(c, s);
  const double delta = wheel.angle;
  const double sin_d = std::sin(delta);
  const double cos_d = std::cos(delta);
  // (C7b) The speed is at least ẋ ≥ v0 − ∫|ẍ| (C2a–C2b), and falls at most at mu·g (C3).
  const double speed_lo = std::max(0.0, c.v0 - std::min(c.mu * c.g * s, z.dv));
  const double v_cg = (c.lr * z.gf + c.lf * z.gr) / c.wheelbase;  // |v| of the CG, body-lateral
  double u_lo = 0.0;
  double uf_lo = 0.0;
  bool valid = was_valid && speed_lo > v_cg;
  if (valid) {
    u_lo = std::sqrt(speed_lo * speed_lo - v_cg * v_cg);
    uf_lo = u_lo * cos_d - z.gf * sin_d;
    valid = u_lo > kMinRollingSpeed_mps && uf_lo > kMinRollingSpeed_mps;
  }
  out.valid = valid;
  out.b.sin_psi = z.psi >= std::numbers::pi / 2.0 ? 1.0 : std::sin(z.psi);
  out.b.yaw_rate = z.r;
  if (!valid) {
    // Plain friction limits; the slip bounds are no longer needed (and no longer tracked).
    out.b.grip_f = out.b.grip_r = out.b.cap_f = out.b.cap_r = c.grip_any;
    out.d.r = (c.lf + c.lr) * c.grip_any / c.iz;
    out.d.psi = z.r;
    return out;
  }
  const double grip_f = front_grip(c, s);
  const double grip_r = c.grip_r_fwd;
  // (C6) |q_f| = |Fx sin δ + Fy cos δ| with Fx² + Fy² ≤ grip², |Fy| ≤ Fiala(|w_f| / u_f).
  // (C6a) and |Fx| ≤ ℓ·grip (C2b: at most the commanded braking, none before the brakes act): the
  // most of a linear function over the disc cut to that box is the radius if the disc's own
  // maximiser (grip sin δ, grip cos δ) lies in the box, else it lies on the edge it violates.
  const double level = std::min(1.0, brake_level(c, s));
  const double push_cap = level * grip_f;
  const auto front_component = [&](double lateral_cap) {
    if (lateral_cap >= grip_f * cos_d && push_cap >= grip_f * sin_d) return grip_f;
    const auto rest = [&](double f) { return std::sqrt(std::max(0.0, grip_f * grip_f - f * f)); };
    const double fy = std::min(lateral_cap, grip_f);
    const double fx = std::min(push_cap, grip_f);
    return std::max(std::min(push_cap, rest(fy)) * sin_d + fy * cos_d,
                    fx * sin_d + std::min(lateral_cap, rest(fx)) * cos_d);
  };
  out.b.grip_f = grip_f;
  out.b.grip_r = grip_r;
  out.d.dv = decel_bound(c, s, sin_d, out.b);
  out.b.cap_f = front_component(fiala_cap(grip_f, c.slope_f, z.gw / uf_lo));
  out.b.cap_r = fiala_cap(grip_r, c.slope_r, z.gr / u_lo);
  // (C7) d|v_f|/dt: the lateral force only pushes v_f outwards while |w_f| ≤ u |sin δ|.
  const double steering_push = front_component(fiala_cap(grip_f, c.slope_f, c.v0 * sin_d / uf_lo));
  out.d.gf = c.a_f * steering_push + c.kappa * out.b.cap_r + c.v0 * z.r;
  // (C7) d|v_r|/dt: the rear force always pulls v_r towards zero.
  out.d.gr = c.kappa * out.b.cap_f + c.v0 * z.r;
  // (C7) d|w_f|/dt, w_f = v_f cos δ − u sin δ; the lateral force always pulls w_f towards zero.
  out.d.gw = c.a_f * push_cap * sin_d + c.kappa * out.b.cap_r + c.v0 * z.r + wheel.rate * (z.gf * sin_d + c.v0) +
             (c.mu * c.g + z.r * v_cg) * sin_d;
  if (start != nullptr) {
    // (C7a) F_yf opposes w_f with at least the ABS floor min(mu F_zf, C_f |tan α_f| / 3) (rolling or
    // braked; the front never locks), |tan α_f| ≥ |w_f| / (v0 + G_f sin Δ); it enters ẇ_f through
    // v̇_f cos δ as a_f cos²δ F_yf. Kept nonnegative so every bound stays nondecreasing.
    // (C7d) Below the ABS cap the front is Fiala's tire under the limit √(N² − (ℓN)²) that the
    // commanded braking ℓN leaves (ℓ at most the brake level of (C2b)); at the cap it slides at the
    // floor, which then exceeds that limit. Fiala's force grows with its limit, so the restoring
    // force is also at least Fiala's under N_min·√(1 − ℓ²), N_min = mu m g lr / L: the full
    // cornering stiffness until the brakes act, and most of it along the ramp.
    const double uf_hi = c.v0 + z.gf * sin_d;
    const double tan_lo = start->gw / uf_hi;
    const double limit = c.grip_f_min * std::sqrt(std::max(0.0, 1.0 - level * level));
    const double floor =
        std::max(std::min(c.grip_f_min, c.stiffness_f * tan_lo / 3.0), fiala_cap(limit, c.stiffness_f, tan_lo));
    out.d.gw = std::max(0.0, out.d.gw - c.a_f * cos_d * cos_d * floor);
  }
  // (C8) Iz ṙ = lf q_f − lr q_r; ψ̇ = r.
  out.d.r = (c.lf * out.b.cap_f + c.lr * out.b.cap_r) / c.iz;
  // (C8a) Once |r| ≥ spin_rate(s) the axles cannot both turn the car further: one of them alone,
  // or the front's braking force through the wheel angle with the rear.
  out.spin_rate = c.v0 * std::tan(delta) / c.wheelbase;
  out.yaw_spin = std::max(c.lf * out.b.cap_f, c.lf * push_cap * sin_d + c.lr * out.b.cap_r) / c.iz;
  out.d.psi = z.r;
  return out;
}

inline Slip advance(const Slip& z, const Slip& d, double step) {
  return {z.gf + step * d.gf, z.gr + step * d.gr,   z.gw + step * d.gw,
          z.r + step * d.r,   z.psi + step * d.psi, z.dv + step * d.dv};
}

// (C8a) The spin rate: from it on the two axles cannot turn the car the same way. Say r > 0. The
// yaw moment lf q_f − lr q_r has both parts positive only if q_r < 0, so v_r > 0 (the rear's force
// opposes its slip), v > lr r and v_f = v + lf r > L r; then w_f = v_f cos δ − u sin δ > L r cos δ
// − u sin δ ≥ 0 once r ≥ u tan δ / L, so F_yf ≤ 0 and q_f = F_xf sin δ + F_yf cos δ ≤ |F_xf| sin Δ.
// With u ≤ v0 and |δ| ≤ Δ: from |r| ≥ v0 tan Δ / L on the yaw moment is at most
// max(lf Q_f, lf |F_xf| sin Δ + lr Q_r) (likewise for r < 0).

// One implicit step from z over `step` with the rates `r` taken at its end (C8): |r| grows at most
// at d.r, and past the spin rate at the step's end (≥ the spin rate on the whole step: Δ is
// nondecreasing) at most at yaw_spin, so after the last moment it was at most
// max(z.r, spin rate) it grew at most at that (C8a). The map from the rates' state to the step's
// end stays nondecreasing.
inline Slip step_to(const Slip& z, const Rates& r, double step) {
  Slip next = advance(z, r.d, step);
  next.r = std::min(next.r, std::max(z.r, r.spin_rate) + step * r.yaw_spin);
  return next;
}

inline bool at_most(const Slip& a, const Slip& b) {
  return a.gf <= b.gf && a.gr <= b.gr && a.gw <= b.gw && a.r <= b.r && a.psi <= b.psi && a.dv <= b.dv;
}

// The functionals bounded by duality (C9): per unit of |q| on each axle, per unit of |p|, and an
// additive term, all nondecreasing in time.
enum class Functional { kCg, kFrontAxle, kRearAxle, kYaw };

struct Table {  // for one functional and one lambda: prefix sums of ĝ·w and ĝ·w·s_mid over cells
  double lambda = 0.0;
  std::vector<double> s0{0.0}, s1{0.0};
};

// The comparison system (C6–C8) and the duality tables (C9–C10), built lazily along the grid.
class Bounder {
 public:
  Bounder(const Setup& c, double base_step, std::vector<double> lambdas)
      : c_(c), base_step_(base_step), lambdas_(std::move(lambdas)) {
    const Rates first = rates_at(c_, 0.0, z_, true);
    valid_ = first.valid;
    times_.push_back(0.0);
    bounds_.push_back(first.b);
    headings_.push_back(0.0);
  }

  [[nodiscard]] double time(int k) const { return times_[static_cast<std::size_t>(k)]; }
  /// |ψ| ≤ this at every s ≤ s_k: the comparison system's heading bound (C8, C8a).
  [[nodiscard]] double heading(int k) const { return headings_[static_cast<std::size_t>(k)]; }
  [[nodiscard]] const Bound& at(int k) const { return bounds_[static_cast<std::size_t>(k)]; }

  // The least grid index k with s_k ≥ s (extending the grid), or -1 beyond the horizon.
  int index_at_or_after(double s) {
    if (s > kHorizon_s) return -1;
    while (times_.back() < s) extend();
    const auto it = std::lower_bound(times_.begin(), times_.end(), s);
    return static_cast<int>(it - times_.begin());
  }

  // Upper bound of functional f at every arrival time T ∈ [s_{k−1}, s_k] for the trajectories that
  // reach the crossing then; `need` is the braking impulse moment that arrival at either end
  // requires. For each lambda the dual value is convex in T, so its larger end value bounds it
  // on the interval; the least over lambda is kept (C10).
  double bound(Functional f, int k, double need_lo, double need_hi) {
    auto& tables = tables_for(f, k);
    const auto hi = static_cast<std::size_t>(k);
    const std::size_t lo = hi - 1;
    const double t_lo = times_[lo];
    const double t_hi = times_[hi];
    double best = kInf;
    for (const Table& t : tables) {
      const double a = t_lo * t.s0[lo] - t.s1[lo] - t.lambda * need_lo;
      const double b = t_hi * t.s0[hi] - t.s1[hi] - t.lambda * need_hi;
      best = std::min(best, std::max(a, b));
    }
    return std::max(best, 0.0);
  }

 private:
  // One step of the comparison system: an upper solution of z1 ≥ z + w·F(s1, z1). F is
  // nondecreasing in s and z, so the piecewise-linear interpolation of such points is an upper
  // solution of the ODE and bounds the true magnitudes (comparison theorem for quasi-monotone
  // systems). A guess is grown until F maps it below itself, then iterated downwards (by
  // monotonicity every iterate stays an upper solution).
  void extend() {
    const double s0 = times_.back();
    const double w = base_step_;  // one width: a finer grid only tightens (every cell takes its right end)
    const double s1 = s0 + w;
    Slip end = z_;
    if (valid_) {
      Slip guess = advance(z_, rates_at(c_, s1, z_, true, &z_).d, 2.0 * w);
      bool found = false;
      for (int tries = 0; tries < 60 && !found; ++tries) {
        const Rates r = rates_at(c_, s1, guess, true, &z_);
        if (!r.valid) break;
        const Slip next = step_to(z_, r, w);
        if (at_most(next, guess)) {
          found = true;
          guess = next;
          for (int down = 0; down < 2; ++down) {
            const Rates rd = rates_at(c_, s1, guess, true, &z_);
            if (!rd.valid) break;
            const Slip lower = step_to(z_, rd, w);
            if (!at_most(lower, guess)) break;
            guess = lower;
          }
        } else {
          guess = {2.0 * std::max(guess.gf, next.gf) + 1e-9,   2.0 * std::max(guess.gr, next.gr) + 1e-9,
                   2.0 * std::max(guess.gw, next.gw) + 1e-9,   2.0 * std::max(guess.r, next.r) + 1e-9,
                   2.0 * std::max(guess.psi, next.psi) + 1e-9, 2.0 * std::max(guess.dv, next.dv) + 1e-9};
        }
      }
      if (found && rates_at(c_, s1, guess, true).valid)
        end = guess;
      else
        valid_ = false;  // from here on only the plain friction limits (and the yaw bounds)
    }
    if (!valid_) {
      // Constant rate: the explicit step at the larger yaw acceleration is exact from above.
      end.r = z_.r + w * (c_.lf + c_.lr) * c_.grip_any / c_.iz;
      end.psi = z_.psi + w * end.r;
    }
    z_ = end;
    times_.push_back(s1);
    bounds_.push_back(rates_at(c_, s1, end, valid_).b);
    headings_.push_back(end.psi);
  }

  std::vector<Table>& tables_for(Functional f, int k) {
    auto& tables = tables_[static_cast<std::size_t>(f)];
    if (tables.empty()) {
      // The yaw functional's multiplier has units rad/s² per m/s²: its grid is scaled by lf·m/Iz.
      const double scale = f == Functional::kYaw ? c_.lf * c_.m / c_.iz : 1.0;
      for (double l : lambdas_) tables.push_back(Table{l * scale});
    }
    while (static_cast<int>(times_.size()) <= k) extend();
    for (std::size_t j = tables.front().s0.size(); j <= static_cast<std::size_t>(k); ++j) add_cell(f, tables, j);
    return tables;
  }

  void add_cell(Functional f, std::vector<Table>& tables, std::size_t k) const {
    const Bound& b = bounds_[k];  // right end of the cell: the largest value in it
    const double w = times_[k] - times_[k - 1];
    const double mid = 0.5 * (times_[k] + times_[k - 1]);
    double a_front = 0.0, a_rear = 0.0, per_p = 0.0, extra = 0.0;
    switch (f) {
      case Functional::kCg:  // Ÿ = (F_bx sin ψ + F_by cos ψ)/m
        a_front = a_rear = 1.0 / c_.m;
        per_p = b.sin_psi / c_.m;
        break;
      case Functional::kFrontAxle:  // cos ψ (a_f q_f + κ q_r) + sin ψ (F_bx/m − lf r²)
        a_front = c_.a_f;
        a_rear = c_.kappa;
        per_p = b.sin_psi / c_.m;
        extra = b.sin_psi * c_.lf * b.yaw_rate * b.yaw_rate;
        break;
      case Functional::kRearAxle:  // cos ψ (κ q_f + a_r q_r) + sin ψ (F_bx/m + lr r²)
        a_front = c_.kappa;
        a_rear = c_.a_r;
        per_p = b.sin_psi / c_.m;
        extra = b.sin_psi * c_.lr * b.yaw_rate * b.yaw_rate;
        break;
      case Functional::kYaw:  // ψ̈ = (lf q_f − lr q_r)/Iz
        a_front = c_.lf / c_.iz;
        a_rear = c_.lr / c_.iz;
        break;
    }
    // (C2a) Before the brakes act neither axle has a longitudinal force: the front's force is its
    // lateral force, so |p_f| = |q_f| tan δ, and p_r = 0.
    const bool unbraked = times_[k] <= c_.brake_dead;
    const double delta = wheel_bound(c_, times_[k]).angle;
    const double tan_delta = std::tan(delta);
    const double level = brake_level(c_, times_[k]);
    const double decel = decel_bound(c_, times_[k], std::sin(delta), b);
    const double full = c_.mu * c_.g;
    for (Table& t : tables) {
      // The arrival constraint's braking, b ≤ (|p_f| + |p_r|)/m + (|q_f| + |q_r|)|sin ψ|/m.
      const double brake_q = t.lambda * b.sin_psi / c_.m;
      const double brake_p = t.lambda / c_.m;
      const double per_q_front = a_front + brake_q;
      const double per_p_all = per_p + brake_p;
      double support = axle_pair_support(per_q_front, a_rear + brake_q, per_p_all, b.grip_f, b.grip_r, b.cap_f, b.cap_r,
                                         c_.total_grip);
      // The front through its lateral force only: |p_f| ≤ |q_f| tan δ, plus ℓ·N_f/cos δ along the
      // brake ramp (C2b: p_f = F_xf/cos δ − q_f tan δ, |F_xf| ≤ ℓ·N_f).
      const double front_steered = (per_q_front + per_p_all * tan_delta) * std::min(b.cap_f, b.grip_f);
      if (unbraked)  // (C2a) and p_r = 0
        support = std::min(support, front_steered + (a_rear + brake_q) * std::min(b.cap_r, b.grip_r));
      else if (level < 1.0)  // (C2b) and the rear in its whole disc (it may be locked)
        support = std::min(support, front_steered + per_p_all * level * b.grip_f / std::cos(delta) +
                                        AxleSupport(a_rear + brake_q, per_p_all, b.cap_r).value(b.grip_r));
      // (C10a) The CG's acceleration is within mu·g in every direction (C2) and its x-part within
      // decel (C2a–C2b), so ÿ + lambda·b = (ẍ, ÿ)·(−lambda, 1) is at most mu·g·√(1 + lambda²),
      // or with the x-part at its bound √((mu·g)² − decel²) + lambda·decel, whatever the heading.
      if (f == Functional::kCg) {
        const double unit = std::sqrt(1.0 + t.lambda * t.lambda);
        const double disc = full * t.lambda / unit <= decel
                                ? full * unit
                                : std::sqrt(std::max(0.0, full * full - decel * decel)) + t.lambda * decel;
        support = std::min(support, disc);
      }
      const double g = support + extra;
      t.s0.push_back(t.s0.back() + g * w);
      t.s1.push_back(t.s1.back() + g * w * mid);
    }
  }

  const Setup& c_;
  double base_step_;
  std::vector<double> lambdas_;
  std::vector<double> times_;
  std::vector<Bound> bounds_;
  std::vector<double> headings_;
  Slip z_;
  bool valid_ = true;
  std::array<std::vector<Table>, 4> tables_;
};

// (C2a) The least progress of the CG along x after the latency. Its x-deceleration is at most
// mu·g; before the brakes act (the brake dead time after the latency, less one simulator step for
// the rear lock's timing) no axle has a longitudinal force, so the only x-force is the front's
// lateral force through the wheel angle and the lateral force through the heading:
// |ẍ| ≤ mu·g·(sin δ̄ + sin ψ̄). (C2b) Along the brake ramp the applied brake level (a step's mean)
// is at most ℓ(s) = (s − t_b + h)/t_r, so |F_xf| ≤ ℓ·(cap share)·mu·F_zf, while a locked rear
// slides at mu·F_zr at once: |ẍ| ≤ (ℓ·N_f + N_r)/m + mu·g·(sin δ̄ + sin ψ̄). Piecewise constant on
// the comparison system's grid up to the ramp's end, mu·g after: knots of the least x-velocity and
// the least travel.
class Braking {
 public:
  Braking(const Setup& c, Bounder& b) : full_(c.mu * c.g), stop_speed_(c.stop_speed) {
    s_.push_back(0.0);
    w_.push_back(c.v0);
    x_.push_back(0.0);
    const double ramp_end = c.brake_ramp > 0.0 ? c.brake_ramp_start + c.brake_ramp : 0.0;
    const double until = std::max(c.brake_dead, ramp_end);
    if (until <= 0.0) return;
    const int last = b.index_at_or_after(until);
    if (last < 0) return;
    for (int k = 1; k <= last && w_.back() > stop_speed_; ++k) {
      double t0 = b.time(k - 1);
      const double cell_end = std::min(b.time(k), until);
      const double sin_delta = std::sin(wheel_bound(c, b.time(k)).angle);
      while (t0 < cell_end && w_.back() > stop_speed_) {
        // The dead time's end splits a cell; each piece takes the bound at its right end (the
        // wheel angle and the comparison system's bounds at the cell's).
        const double t1 = t0 < c.brake_dead ? std::min(cell_end, c.brake_dead) : cell_end;
        const double d = decel_bound(c, t1, sin_delta, b.at(k));
        double h = t1 - t0;
        if (d > 0.0) h = std::min(h, (w_.back() - stop_speed_) / d);  // falls to the stop speed inside
        decel_.push_back(d);
        x_.push_back(x_.back() + w_.back() * h - 0.5 * d * h * h);
        w_.push_back(w_.back() - d * h);
        s_.push_back(t0 + h);
        t0 = t1;
      }
    }
  }
  /// Least x-travel (from the end of the latency) before the x-velocity can fall to the stop speed.
  [[nodiscard]] double stop_travel() const {
    const double w = w_.back();
    return x_.back() + std::max(0.0, w * w - stop_speed_ * stop_speed_) / (2.0 * full_);
  }
  /// Latest time after the latency the CG can first reach `travel` (< stop_travel()).
  [[nodiscard]] double latest(double travel) const {
    for (std::size_t k = 0; k + 1 < s_.size(); ++k) {
      if (travel > x_[k + 1]) continue;
      const double rest = travel - x_[k];
      const double d = decel_[k];
      const double w = w_[k];
      return s_[k] + (d > 0.0 ? (w - std::sqrt(std::max(0.0, w * w - 2.0 * d * rest))) / d : rest / w);
    }
    const double w = w_.back();
    const double rest = travel - x_.back();
    return s_.back() + (w - std::sqrt(w * w - 2.0 * full_ * rest)) / full_;
  }

 private:
  double full_, stop_speed_;
  std::vector<double> s_, w_, x_, decel_;
};

}  // namespace emrm::sim::certificate_bounds
