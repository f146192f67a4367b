#pragma once

// An imported OpenSCENARIO scenario as a scenario family (docs/import.md, "A scenario as a family"):
// the family "openscenario" lays out each cell by playing the scenario's storyboard open loop with
// the cell's factors set (its declared parameters that are factors, the ego's speed), finding the
// threat onset — the first moment the ego's time to collision with another road user falls to the
// cell's TTC — and handing over there: from the onset on, every other road user runs on the track
// it played, on the straight road the ego drives, and the strategies drive the ego.

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/sim/family.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::openscenario {

/// The family "openscenario" (sim::ScenarioFamilyInfo): its factors are the ego's speed, the TTC
/// at the onset, the road's friction, then the scene's `openscenario.factors` in order.
[[nodiscard]] sim::ScenarioFamilyInfo scenario_family();

/// What `emrm import` chooses that a scenario file does not say.
struct ImportChoices {
  std::string ego;  ///< the entity the EMRM drives; empty: one named Ego, ego or hero, else the first vehicle
  /// The declared numeric parameters the scene makes factors (`emrm import --factors`), at most
  /// sim::kMaxImportedFactors; empty: every one the scenario declares.
  std::vector<std::string> factors;
};

/// The scene an OpenSCENARIO file makes: family openscenario, the file (absolute), the ego, its
/// footprint from the ego's bounding box, the chosen declared numeric parameters as factors, else
/// every one (at most sim::kMaxImportedFactors: more is an InputError that asks to choose), the
/// parameter that sets the ego's speed when its Init takes it from one; the rest at its defaults.
/// Throws InputError as the reader does, for an ego that is not a vehicle of the scenario, and for
/// a chosen factor that is no numeric parameter the scenario declares.
[[nodiscard]] sim::SceneConfig scene_of(const std::filesystem::path& file, const ImportChoices& choices = {});

/// Registers the family and the ".xosc" scene reader (load_scene_config, hence every command's
/// --scene) for as long as it lives; each program's main holds one.
class Registration {
 public:
  Registration();

 private:
  sim::FamilyRegistration family_;
  sim::SceneReaderRegistration reader_;
};

}  // namespace emrm::openscenario
