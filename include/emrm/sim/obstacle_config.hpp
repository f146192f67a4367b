#pragma once

// A body that enters the road and stops in the ego's way, as a scene file describes it: the
// T-junction's crossing truck (`truck:`), the highway's truck and deer (`highway.truck:`,
// `highway.deer:`). Its footprint, mass and yaw inertia, the speed it has when the hazard appears,
// and the deceleration with which it brakes to a standstill (docs/scene-yaml.md, docs/families.md).

#include "emrm/core/config.hpp"

namespace emrm::sim {

/// The defaults are the T-junction's rigid truck.
struct ObstacleConfig {
  double length_m = 10.0;  ///< along its heading
  double width_m = 2.5;
  double mass_kg = 12000.0;
  double yaw_inertia_kgm2 = 130000.0;  ///< ≈ m (L² + W²) / 12
  double speed_kph = 10.0;             ///< when the hazard appears (a cell may override it)
  double decel_mps2 = 4.0;             ///< it brakes to a standstill from t = 0; 0: it keeps going

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, length_m, core::positive);
    EMRM_FIELD(a, width_m, core::positive);
    EMRM_FIELD(a, mass_kg, core::positive);
    EMRM_FIELD(a, yaw_inertia_kgm2, core::positive);
    EMRM_FIELD(a, speed_kph, core::non_negative);
    EMRM_FIELD(a, decel_mps2, core::non_negative);
  }
};

}  // namespace emrm::sim
