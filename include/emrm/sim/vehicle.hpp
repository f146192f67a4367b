#pragma once

// Vehicle dynamics (docs/physics.md). The default model is a single-track (bicycle) model with
// Fiala brush tires per axle, a friction circle per axle, quasi-static longitudinal load
// transfer and a blend to the kinematic model at low speed; a kinematic bicycle model is kept
// for comparison. Models are picked by name from a registry (VehicleModelRegistration adds one);
// all are pure and thread-safe.

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/config.hpp"

namespace emrm::sim {

inline constexpr double kGravity_mps2 = 9.81;
inline constexpr double kKphPerMps = 3.6;

/// Ego vehicle parameters; defaults are CommonRoad vehicle 2 (BMW 320i), except the front cornering
/// stiffness, softened for an understeer gradient of 2.2 deg/g (docs/physics.md).
struct VehicleParams {
  double length_m = 4.508;
  double width_m = 1.610;
  double mass_kg = 1093.0;
  double yaw_inertia_kgm2 = 1792.0;
  double cg_to_front_axle_m = 1.156;  ///< l_f
  double cg_to_rear_axle_m = 1.423;   ///< l_r
  double cg_height_m = 0.575;
  double max_steer_rad = 0.6;  ///< road-wheel angle
  double max_steer_rate_radps = 0.8;
  double front_cornering_stiffness_n_per_rad = 70000.0;  ///< effective axle value; independent of mu
  double rear_cornering_stiffness_n_per_rad = 105000.0;
  double kinematic_blend_speed_mps = 1.0;  ///< below this the kinematic model takes over

  [[nodiscard]] double wheelbase_m() const { return cg_to_front_axle_m + cg_to_rear_axle_m; }
  /// Overhangs are equal front and rear: CG to front bumper.
  [[nodiscard]] double cg_to_front_m() const { return cg_to_front_axle_m + (length_m - wheelbase_m()) / 2.0; }
  [[nodiscard]] double cg_to_rear_m() const { return length_m - cg_to_front_m(); }

  template <class A>
  void serialize(A& a) {
    // The ranges hold every road vehicle from a microcar to a loaded articulated truck (docs/scene-yaml.md);
    // outside them the value is a slip of unit, and the message says which.
    EMRM_FIELD(a, length_m, core::plausible(1.0, 30.0, "a length", "m", "", "in millimetres?"));
    EMRM_FIELD(a, width_m, core::plausible(0.4, 3.0, "a width", "m", "", "in millimetres?"));
    EMRM_FIELD(a, mass_kg, core::plausible(50.0, 60000.0, "a mass", "kg", "in tonnes?", "in grams?"));
    EMRM_FIELD(a, yaw_inertia_kgm2, core::plausible(10.0, 2.0e6, "a yaw inertia", "kg·m²", "in tonne·m²?", ""));
    EMRM_FIELD(a, cg_to_front_axle_m, core::plausible(0.1, 15.0, "a CG-to-axle distance", "m", "", "in millimetres?"));
    EMRM_FIELD(a, cg_to_rear_axle_m, core::plausible(0.1, 15.0, "a CG-to-axle distance", "m", "", "in millimetres?"));
    EMRM_FIELD(a, cg_height_m, core::plausible(0.1, 4.0, "a CG height", "m", "", "in millimetres?"));
    EMRM_FIELD(a, max_steer_rad, core::open_interval(0.0, std::numbers::pi / 2, "(0, pi/2)"));
    EMRM_FIELD(
        a, max_steer_rate_radps,
        core::plausible(0.01, 20.0, "a steering rate of the road wheels", "rad/s", "", "in degrees per second?"));
    EMRM_FIELD(a, front_cornering_stiffness_n_per_rad,
               core::plausible(500.0, 5.0e6, "an axle's cornering stiffness", "N/rad", "in kN/rad?", ""));
    EMRM_FIELD(a, rear_cornering_stiffness_n_per_rad,
               core::plausible(500.0, 5.0e6, "an axle's cornering stiffness", "N/rad", "in kN/rad?", ""));
    EMRM_FIELD(a, kinematic_blend_speed_mps, core::non_negative);
    // Overhangs are (length − wheelbase)/2 each; a negative one would put the bumper behind the axle.
    a.ensure(!(wheelbase_m() > length_m), "length_m",
             "expected the car to be at least as long as its wheelbase ({} m), got {} m", wheelbase_m(), length_m);
  }
};

/// Checks every field of the parameters (sizes, masses, stiffnesses > 0; the steering limit in
/// (0, pi/2); a car at least as long as its wheelbase). Throws core::ConfigError (an InputError)
/// naming the field: "vehicle: length_m: expected ...".
void validate(const VehicleParams& params);

/// The state of the vehicle: CG position and yaw in the road frame, velocities in the body frame.
struct VehicleState {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
  double vx_mps = 0.0;  ///< body-frame longitudinal velocity
  double vy_mps = 0.0;  ///< body-frame lateral velocity (left positive)
  double yaw_rate_radps = 0.0;
  double steer_rad = 0.0;  ///< road-wheel steering angle (left positive)

  /// sqrt(vx^2 + vy^2); inline, as the rollouts ask for it several times a step.
  [[nodiscard]] double speed_mps() const { return std::sqrt(vx_mps * vx_mps + vy_mps * vy_mps); }
  /// Body slip angle atan2(vy, vx); 0 at standstill.
  [[nodiscard]] double slip_angle_rad() const;
};

/// What the planner commands; held constant over a control interval.
struct Control {
  double steer_rate_radps = 0.0;  ///< clamped to ±max_steer_rate; the angle stops at ±max_steer
  /// 0…1, fraction of the friction limit mu F_z commanded on each rolling axle; the ABS caps it so that
  /// a cornering axle keeps its combined-slip lateral force (docs/physics.md)
  double brake = 0.0;
  bool rear_lock = false;  ///< rear wheels locked: the rear axle slides at mu·F_z against its velocity
};

/// Forces and state of one axle, for diagnostics and constraints.
struct AxleForces {
  double normal_load_n = 0.0;  ///< F_z after load transfer
  double slip_angle_rad = 0.0;
  double longitudinal_n = 0.0;   ///< F_x in the wheel frame
  double lateral_n = 0.0;        ///< F_y in the wheel frame
  double lateral_limit_n = 0.0;  ///< sqrt((mu F_z)^2 - F_x^2)
  /// At the friction limit: beyond the Fiala sliding angle, held there by the ABS, or locked.
  bool saturated = false;
};

struct TireForces {
  AxleForces front;
  AxleForces rear;
};

/// A vehicle model: state derivative plus fixed-step integration.
class VehicleModel {
 public:
  explicit VehicleModel(VehicleParams params) : params_(params) {}
  virtual ~VehicleModel() = default;

  [[nodiscard]] virtual std::string_view name() const = 0;
  /// d(state)/dt under `control` on a road of friction `mu`. `steer_rad` of the result is the
  /// (limited) steering rate.
  [[nodiscard]] virtual VehicleState derivative(const VehicleState& s, const Control& u, double mu) const = 0;
  /// Tire forces at this state (zeros for models without tires).
  [[nodiscard]] virtual TireForces tire_forces(const VehicleState& s, const Control& u, double mu) const = 0;
  /// Whether the rear axle is saturated at a slip angle beyond `min_slip_angle_rad` (dodge's
  /// constraint): tire_forces(s, u, mu).rear.saturated && |its slip_angle_rad| > min_slip_angle_rad,
  /// which a model may answer more cheaply, but always the same.
  [[nodiscard]] virtual bool rear_axle_sliding(const VehicleState& s, const Control& u, double mu,
                                               double min_slip_angle_rad) const;

  /// One classic RK4 step of `dt_s`. Keeps the steering angle within its limit, and a vehicle
  /// that comes to rest under braking stays at rest (no creeping backwards).
  [[nodiscard]] VehicleState step(const VehicleState& s, const Control& u, double mu, double dt_s) const;

  [[nodiscard]] const VehicleParams& params() const noexcept { return params_; }

 protected:
  VehicleParams params_;
};

/// Single-track model with Fiala brush tires ("single_track_fiala", docs/physics.md): friction circle
/// per axle, quasi-static longitudinal load transfer, ABS braking up to the friction limit that
/// leaves a cornering axle its combined-slip lateral force, a sliding locked rear axle, and a blend to
/// the kinematic model below `kinematic_blend_speed_mps`.
class SingleTrackFiala final : public VehicleModel {
 public:
  static constexpr std::string_view kName = "single_track_fiala";
  using VehicleModel::VehicleModel;

  [[nodiscard]] std::string_view name() const override { return kName; }
  [[nodiscard]] VehicleState derivative(const VehicleState& s, const Control& u, double mu) const override;
  /// Axle forces of the dynamic (unblended) model. Slip angles lie in [-pi/2, pi/2]: a wheel
  /// moving backwards is measured from its backward direction, so the lateral force always
  /// opposes the lateral sliding.
  [[nodiscard]] TireForces tire_forces(const VehicleState& s, const Control& u, double mu) const override;
  /// Decides from the rear slip angle first, solving the axles only when it is beyond the limit.
  [[nodiscard]] bool rear_axle_sliding(const VehicleState& s, const Control& u, double mu,
                                       double min_slip_angle_rad) const override;
};

/// Kinematic single-track model ("kinematic_bicycle"): no tires; the CG moves at the slip angle
/// beta = atan(l_r tan(delta) / L); braking decelerates at brake*mu*g, a rear lock at mu*g. For
/// comparison only: it has no friction limit on lateral acceleration.
class KinematicBicycle final : public VehicleModel {
 public:
  static constexpr std::string_view kName = "kinematic_bicycle";
  using VehicleModel::VehicleModel;

  [[nodiscard]] std::string_view name() const override { return kName; }
  [[nodiscard]] VehicleState derivative(const VehicleState& s, const Control& u, double mu) const override;
  /// Always zeros: the model has no tires.
  [[nodiscard]] TireForces tire_forces(const VehicleState& s, const Control& u, double mu) const override;
};

namespace detail {

/// Below this speed the rolling direction of a wheel is undefined.
inline constexpr double kRollingEpsilon_mps = 1e-3;
/// Rolling direction of a wheel moving at `u_mps` along itself: ±1, ramping linearly through zero
/// within ±kRollingEpsilon_mps so that braking forces vanish at rest instead of chattering.
[[nodiscard]] inline double rolling_sign(double u_mps) {
  // Well outside the ramp the quotient is beyond ±1 for certain: the clamp's bound without the division.
  if (std::abs(u_mps) >= 2.0 * kRollingEpsilon_mps) return std::copysign(1.0, u_mps);
  return std::clamp(u_mps / kRollingEpsilon_mps, -1.0, 1.0);
}

/// Commanded steering rate limited to ±max_steer_rate, and zero at the angle limit when pushing
/// further out.
[[nodiscard]] double limited_steer_rate(const VehicleParams& p, const VehicleState& s, const Control& u);

/// d(vx, vy, r)/dt of the kinematic model for a signed path acceleration `speed_rate_mps2`. Also
/// relaxes vx, vy and r towards the kinematic values for the current speed and steering, so a
/// state that is not (yet) kinematic, e.g. handed over by the dynamic model, converges to one; the
/// translational part of that correction is at most `max_correction_mps2` (friction pays for it).
struct KinematicBodyRates {
  double vx_mps2 = 0.0;
  double vy_mps2 = 0.0;
  double yaw_rate_radps2 = 0.0;
};
[[nodiscard]] KinematicBodyRates kinematic_body_rates(const VehicleParams& p, const VehicleState& s,
                                                      double steer_rate_radps, double speed_rate_mps2,
                                                      double max_correction_mps2);

}  // namespace detail

/// A vehicle model as the registry knows it: picked by name from a scene's
/// `simulation.vehicle_model`, made for the scene's parameters.
struct VehicleModelInfo {
  std::string name;
  std::string description;
  /// Makes the model for parameters that validate() accepted.
  std::function<std::unique_ptr<VehicleModel>(const VehicleParams&)> make;
  /// Whether the unavoidability certificate's bound (certificate.hpp) is derived for this model's
  /// dynamics. Without one no cell is certified unavoidable: O and R cells stay `undecided`, and the
  /// cell's result says why (CellResult::no_certificate).
  bool certificate_bound = false;
};

/// Registers a vehicle model for as long as the object lives (the registry of strategies and planners:
/// a program or a test adds its own model, `emrm simulate` and the sweeps use it by name). The shipped
/// models, single_track_fiala and kinematic_bicycle, are always registered. Throws UsageError for a
/// name already registered or a model without a factory.
class VehicleModelRegistration {
 public:
  explicit VehicleModelRegistration(VehicleModelInfo info);
  ~VehicleModelRegistration();
  VehicleModelRegistration(const VehicleModelRegistration&) = delete;
  VehicleModelRegistration& operator=(const VehicleModelRegistration&) = delete;

 private:
  std::string name_;
};

/// The registered model of that name, if any (a copy: the registry may change afterwards).
[[nodiscard]] std::optional<VehicleModelInfo> find_vehicle_model(std::string_view name);

/// Creates a registered model by name after validate(params). Throws emrm::Error for an unknown name
/// (the message lists the known ones), core::ConfigError for bad parameters. The model's own
/// functions expect validated parameters and check nothing.
[[nodiscard]] std::unique_ptr<VehicleModel> make_vehicle_model(std::string_view name, const VehicleParams& params);
/// Names known to make_vehicle_model, in registration order.
[[nodiscard]] std::vector<std::string> vehicle_model_names();

}  // namespace emrm::sim
