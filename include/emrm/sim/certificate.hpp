#pragma once

// Unavoidability certificates (docs/physics.md, "Unavoidability certificates"): a sound bound on
// what the single-track Fiala model can do in a cell, strong enough to show that every trajectory
// touches the truck or leaves the drivable area. Cheap (about a millisecond, against tens for a
// search), so a sweep can run it for every cell before any search.

#include <optional>
#include <string>

#include "emrm/sim/scene.hpp"

namespace emrm::sim {

/// A proof that no control of the vehicle model avoids the truck in this cell: every trajectory
/// the model can produce touches the truck or leaves the drivable area. Holds the numbers a checker
/// needs to re-derive the claim without trusting the code that found it.
///
/// The claim is made at one event every trajectory must pass through: the moment its centre of
/// gravity first reaches `crossing_x_m`. Before it could come to rest the CG must reach
/// `stop_reach_x_m` > crossing_x_m, so every trajectory that has not touched or left the road
/// by then does reach it, somewhen in [window_start_s, window_end_s]; at that moment the bound
/// puts some point of the car inside the truck (or beyond an edge) by at least margin_m.
struct Certificate {
  std::string method = "lateral-reach";  ///< which bound proved it
  /// How far short of avoiding the best relaxed trajectory falls (> 0): the least depth by which
  /// the car's footprint overlaps the truck or crosses an edge at the crossing, over every
  /// arrival time and every relaxed trajectory.
  double margin_m = 0.0;
  /// "disc": the disc of radius width/2 about the CG, once the CG is in the truck's x-range;
  /// "side": the car's cross-section at the truck's near side, with the heading bounded;
  /// "flank": the same at the truck's far side (a truck that comes down onto the car's flank).
  std::string witness;
  double crossing_x_m = 0.0;     ///< x of the CG at the crossing event
  double heading_cap_rad = 0.0;  ///< "side", "flank": |heading| at the crossing is shown to be at most this
  double window_start_s = 0.0;   ///< earliest time the CG can reach crossing_x_m
  double window_end_s = 0.0;     ///< latest (braking at mu·g from the end of the latency)
  double stop_reach_x_m = 0.0;   ///< least x the CG reaches before its speed can fall to the stop threshold
  double step_s = 0.0;           ///< time step of the bound's integration
  CellInput cell;                ///< the cell it was made for
  double latency_s = 0.0;        ///< the scene's perception latency it was made for
  ActuationConfig actuation;     ///< the scene's actuators it was made for (latency_s included)
};

/// A certificate for the cell, or nothing when the bound cannot prove unavoidability (always
/// nothing where no_certificate_bound says why). Pure,
/// cheap (0.3–0.7 ms on average over the fine grid, a few ms in the slowest cells; it is run for
/// every cell of every sweep before any search).
[[nodiscard]] std::optional<Certificate> certify_unavoidable(const Scene& scene);

/// Why no cell of this scene can carry a certificate, or nothing when cells can: the scene's vehicle
/// model is registered without a certificate bound (VehicleModelInfo::certificate_bound), or its
/// time step is above the bound's 0.02 s.
[[nodiscard]] std::optional<std::string> no_certificate_bound(const SceneConfig& config);

/// Re-derives the certificate's claim independently (for `emrm verify`): true when it holds. It
/// checks that the certificate names this scene's cell, latency and actuators, and re-evaluates its witness
/// from scratch, ignoring the certificate's numbers but the witness, with a denser set of
/// multipliers (each sound on its own) at half the certifier's step and, failing that, at its
/// step, requiring the least margin kCertificateMinMargin_m.
[[nodiscard]] bool check_certificate(const Scene& scene, const Certificate& certificate);

/// The least penetration a certificate must show (metres, in x and in y): it covers the
/// integrator's error and the contact test's tolerance (docs/physics.md).
inline constexpr double kCertificateMinMargin_m = 0.02;

}  // namespace emrm::sim
