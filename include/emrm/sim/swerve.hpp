#pragma once

// The swerve family: steer in towards a free side at the full rate to a peak, hold, counter-steer,
// hold, straighten, braking throughout (at a level of its own while steering in, holding and
// after), then the full-stop tail. The reference planner enumerates a grid of it (docs/planner.md,
// "Reference planner"); the falsifier optimises over it continuously ("The falsifier").

#include <vector>

#include "emrm/sim/controls.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {

/// One member of the swerve family.
struct Swerve {
  double side = 1.0;            ///< +1 towards the right (negative y), −1 towards the left
  double peak_rad = 0.1;        ///< steer-in angle (clamped to the car's limit)
  double hold_s = 0.0;          ///< held at the peak
  double counter = 0.0;         ///< counter-steer to −counter × peak
  double counter_hold_s = 0.3;  ///< held there
  double brake = 0.0;           ///< brake level (0…1) while steering in
  double brake_hold = 0.0;      ///< while holding at the peak
  double brake_out = 0.0;       ///< and from the counter-steer on
  bool rear_lock = false;       ///< rear wheels locked during the hold
  bool lock_in = false;         ///< and while steering in (a handbrake kick)
};

/// The plan of `swerve` from t = 0 (the perception latency's wait first, when the scene has one);
/// the tail is Tail::full_stop().
[[nodiscard]] std::vector<ControlSegment> swerve_plan(const Scene& scene, const Swerve& swerve);

/// The free sides of the scene's hazard (+1 right, −1 left), the right first.
[[nodiscard]] std::vector<double> free_sides(const Scene& scene);

/// The reference planner's grid of the family: peaks {0.1, 0.2, 0.3, 0.45, 0.6} rad, holds
/// {0, 0.2, 0.4, 0.7, 1.0} s, counters {0, 0.5, 1}, counter holds {0.3, 0.6} s, brakes {0, 0.3, 0.6}
/// (the same in and out), with the rear locked or not when `allow_rear_lock`, towards each free side.
[[nodiscard]] std::vector<Swerve> reference_swerves(const Scene& scene, bool allow_rear_lock);

/// The falsifier's grid: the reference grid, and with `allow_rear_lock` also handbrake kicks (the
/// rear locked and the brakes full while steering in: peaks as the reference's, holds {0, 0.2, 0.4} s,
/// counters {0, 0.5, 1}, counter hold 0.3 s, the rear locked in the hold or not).
[[nodiscard]] std::vector<Swerve> falsifier_swerves(const Scene& scene, bool allow_rear_lock);

}  // namespace emrm::sim
