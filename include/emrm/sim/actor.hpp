#pragma once

// The other road users of a scene and their open-loop motion (docs/families.md, draft): a body of
// a kind (car, truck, pedestrian, cyclist, animal, static object) with a rectangular footprint, a
// mass, and a closed-form motion set by the cell's factors. Road frame: x along the road (the ego
// drives +x), y to the left.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/core/enum_names.hpp"
#include "emrm/core/geometry.hpp"

namespace emrm::sim {

/// What an actor is: it decides how a contact with it harms (docs/families.md, "Harm").
enum class ActorKind : std::uint8_t { kCar, kTruck, kPedestrian, kCyclist, kAnimal, kStaticObject };

/// An actor's body: footprint, mass and yaw inertia (a non-positive mass: immovable).
struct ActorBody {
  ActorKind kind = ActorKind::kCar;
  double length_m = 4.5;
  double width_m = 1.8;
  double mass_kg = 1500.0;
  double yaw_inertia_kgm2 = 2500.0;
  std::string name{};  ///< what the scene calls it: "truck", "deer"
};

/// Where an actor is at a time, and how fast it moves (road frame).
struct ActorState {
  core::OrientedBox box;
  core::Vec2 velocity_mps;
};

/// An open-loop motion given as samples rather than in closed form: an imported scenario's storyboard
/// played open loop (docs/import.md). The box's centre, heading and speed every `dt_s` from t = 0;
/// between samples the pose is interpolated linearly (the heading along the shorter way round), the
/// velocity is that of the interpolated path (the interval's secant); after the last sample the actor
/// goes on straight at the last sample's speed (it rests if that is 0).
struct Track {
  struct Sample {
    double x_m = 0.0, y_m = 0.0, heading_rad = 0.0, speed_mps = 0.0;
  };
  double dt_s = 0.01;
  std::vector<Sample> samples;

  /// Throws std::invalid_argument for no samples, a spacing that is not finite and positive, or a
  /// sample with a value that is not finite or a negative speed.
  Track(double dt, std::vector<Sample> points);
  /// The fastest any point of a box of that size moves: the speed, plus the turn rate times the
  /// half-diagonal, over every interval (O(samples): Actor keeps its own).
  [[nodiscard]] double top_speed_mps(double length_m, double width_m) const noexcept;
  /// From when the actor stands for good: the first sample from which every speed is 0 (and the
  /// pose no longer changes); +∞ when it moves at the last sample.
  [[nodiscard]] double rest_time_s() const noexcept { return rest_time_s_; }
  /// The interpolated centre, heading and velocity at time t (t < 0 counts as 0).
  [[nodiscard]] Sample at(double t_s, core::Vec2* velocity_mps) const noexcept;

 private:
  double rest_time_s_ = 0.0;
};

/// An open-loop motion in closed form, enough for the shipped families. The middle of the actor's
/// leading edge starts at `front` and moves along the unit vector `direction` (the actor's heading)
/// at `speed_mps`; from `brake_from_s` on it brakes at `decel_mps2` until it stands (0: it keeps its
/// speed); meanwhile it drifts sideways, along +y, at `lateral_mps` for `lateral_for_s` (a car that
/// cuts in: its box translates, it does not turn). A static object has speed 0. Axis-aligned
/// directions are exact ({0, -1}), so a motion along an axis moves no other coordinate.
struct ActorMotion {
  core::Vec2 front;
  core::Vec2 direction{1.0, 0.0};
  double speed_mps = 0.0;
  double decel_mps2 = 0.0;
  double brake_from_s = 0.0;
  double lateral_mps = 0.0;
  double lateral_for_s = 0.0;
  /// Set: the motion is these samples instead (Track), and the fields above are unused but for
  /// `direction`, the heading at t = 0.
  std::shared_ptr<const Track> track{};

  /// The distance travelled along `direction` by time t (t < 0 counts as 0).
  [[nodiscard]] double travelled_m(double t_s) const noexcept;
  /// The speed along `direction` at time t.
  [[nodiscard]] double speed_at_mps(double t_s) const noexcept;
  /// The sideways offset (along +y) at time t.
  [[nodiscard]] double lateral_m(double t_s) const noexcept;
  /// The time the actor comes to rest along `direction`, or +∞ when it never does.
  [[nodiscard]] double rest_time_s() const noexcept;
  /// The middle of the leading edge at time t.
  [[nodiscard]] core::Vec2 front_at(double t_s) const noexcept;
};

/// One actor of a scene: its body and its motion.
class Actor {
 public:
  Actor() = default;
  Actor(const ActorBody& body, const ActorMotion& motion) noexcept;

  [[nodiscard]] const ActorBody& body() const noexcept { return body_; }
  [[nodiscard]] const ActorMotion& motion() const noexcept { return motion_; }
  /// The actor at time t (t < 0 counts as 0).
  [[nodiscard]] ActorState at(double t_s) const noexcept;
  /// Its heading: the direction of its motion (a Track's: at t = 0).
  [[nodiscard]] double heading_rad() const noexcept { return heading_rad_; }
  /// The fastest any point of it ever moves: its motion only slows along its direction and drifts
  /// sideways at a constant speed; a Track's is its fastest interval's, its corners' turning included.
  [[nodiscard]] double top_speed_mps() const noexcept { return top_speed_mps_; }
  /// The lowest and the highest y its footprint covers at time t: exact for a motion along an axis
  /// (the leading edge is motion().front_at(t)), from the box's corners otherwise.
  [[nodiscard]] std::pair<double, double> y_extent_at(double t_s) const noexcept;

 private:
  ActorBody body_;
  ActorMotion motion_;
  double heading_rad_ = 0.0;
  double top_speed_mps_ = 0.0;
  core::Vec2 half_length_;  // from the middle of the box to the middle of its leading edge
};

// Defined here: the rollout asks for the hazard twice a step.

inline double ActorMotion::travelled_m(double t_s) const noexcept {
  const double t = std::max(t_s, 0.0);
  if (t <= brake_from_s) return speed_mps * t;
  const double cruise_m = brake_from_s > 0.0 ? speed_mps * brake_from_s : 0.0;
  const double after_s = t - brake_from_s;
  if (decel_mps2 <= 0.0) return cruise_m + speed_mps * after_s;
  const double moving_s = std::min(after_s, speed_mps / decel_mps2);  // it stops at v/a and stays
  return cruise_m + (speed_mps * moving_s - 0.5 * decel_mps2 * moving_s * moving_s);
}

inline double ActorMotion::speed_at_mps(double t_s) const noexcept {
  const double t = std::max(t_s, 0.0);
  if (t <= brake_from_s || decel_mps2 <= 0.0) return speed_mps;
  return std::max(speed_mps - decel_mps2 * (t - brake_from_s), 0.0);
}

inline double ActorMotion::lateral_m(double t_s) const noexcept {
  return lateral_mps * std::clamp(t_s, 0.0, std::max(lateral_for_s, 0.0));
}

inline double ActorMotion::rest_time_s() const noexcept {
  if (track) return track->rest_time_s();
  if (!(speed_mps > 0.0)) return 0.0;
  if (decel_mps2 <= 0.0) return std::numeric_limits<double>::infinity();
  return brake_from_s + speed_mps / decel_mps2;
}

inline core::Vec2 ActorMotion::front_at(double t_s) const noexcept {
  core::Vec2 at = front + direction * travelled_m(t_s);
  if (lateral_mps != 0.0) at.y += lateral_m(t_s);
  return at;
}

inline Actor::Actor(const ActorBody& body, const ActorMotion& motion) noexcept
    : body_(body),
      motion_(motion),
      top_speed_mps_(motion.track ? motion.track->top_speed_mps(body.length_m, body.width_m)
                                  : motion.speed_mps + std::abs(motion.lateral_mps)),
      half_length_(motion.direction * (body.length_m / 2.0)) {
  const core::Vec2 d = motion.direction;
  if (d.x == 0.0)  // along an axis: exact
    heading_rad_ = std::copysign(std::numbers::pi / 2.0, d.y);
  else if (d.y == 0.0)
    heading_rad_ = d.x > 0.0 ? 0.0 : std::numbers::pi;
  else
    heading_rad_ = std::atan2(d.y, d.x);
}

inline ActorState Actor::at(double t_s) const noexcept {
  const double t = std::max(t_s, 0.0);
  ActorState out;
  out.box.length_m = body_.length_m;
  out.box.width_m = body_.width_m;
  if (motion_.track) {
    const Track::Sample p = motion_.track->at(t, &out.velocity_mps);
    out.box.center = {p.x_m, p.y_m};
    out.box.heading_rad = p.heading_rad;
    return out;
  }
  out.box.center = motion_.front_at(t) - half_length_;
  out.box.heading_rad = heading_rad_;
  out.velocity_mps = motion_.direction * motion_.speed_at_mps(t);
  if (motion_.lateral_mps != 0.0 && t < motion_.lateral_for_s) out.velocity_mps.y += motion_.lateral_mps;
  return out;
}

inline std::pair<double, double> Actor::y_extent_at(double t_s) const noexcept {
  const core::Vec2 d = motion_.direction;
  if (!motion_.track) {
    const core::Vec2 front = motion_.front_at(t_s);
    if (d.x == 0.0)
      return d.y < 0.0 ? std::pair{front.y, front.y + body_.length_m} : std::pair{front.y - body_.length_m, front.y};
    if (d.y == 0.0) return {front.y - body_.width_m / 2.0, front.y + body_.width_m / 2.0};
  }
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  for (const core::Vec2& corner : at(t_s).box.corners()) {
    low = std::min(low, corner.y);
    high = std::max(high, corner.y);
  }
  return {low, high};
}

}  // namespace emrm::sim

template <>
struct emrm::core::EnumNames<emrm::sim::ActorKind> {
  static constexpr std::array<std::pair<emrm::sim::ActorKind, std::string_view>, 6> kNames{{
      {emrm::sim::ActorKind::kCar, "car"},
      {emrm::sim::ActorKind::kTruck, "truck"},
      {emrm::sim::ActorKind::kPedestrian, "pedestrian"},
      {emrm::sim::ActorKind::kCyclist, "cyclist"},
      {emrm::sim::ActorKind::kAnimal, "animal"},
      {emrm::sim::ActorKind::kStaticObject, "static_object"},
  }};
};
