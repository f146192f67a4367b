#pragma once

// Scenario families (docs/families.md): a family is a kind of scene — the T-junction, a highway
// obstacle, a cut-in — that a scene file names (`family: tjunction`). It owns its factors (the
// factor table) and, for each cell, lays out the road, the other road users (actors) and where the
// ego starts. Families are registered by name like strategies and vehicle models: the shipped ones
// are always there, and a program or a test adds its own with a FamilyRegistration.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/sim/actor.hpp"
#include "emrm/sim/factors.hpp"
#include "emrm/sim/road.hpp"

namespace emrm::sim {

struct SceneConfig;

/// One cell's scene as its family lays it out, in the road frame; the ego's front bumper is at
/// x = 0 when the hazard appears (t = 0), and it drives +x.
struct SceneLayout {
  Road road;
  /// The other road users. The first is the hazard: the cell's time to collision is measured
  /// against it, and an ego whose rear is beyond `passed_x_m` has got past it.
  std::vector<Actor> actors;
  double ego_y_m = 0.0;  ///< the ego's centre line (its lane)
  /// The ego's speed at t = 0 when the family sets it (an imported scenario's: at the threat onset);
  /// unset, the cell's speed factor.
  std::optional<double> ego_speed_mps{};
  /// From the ego's front bumper to the hazard's near side at t = 0 (v·TTC for a hazard across the
  /// ego's path).
  double initial_distance_m = 0.0;
  /// The hazard's far side at t = 0; it moves with the hazard along x (Scene::passed_x_m).
  double passed_x_m = 0.0;
  /// Why the cell cannot be laid out as a scenario (factors that contradict each other: a cut-in
  /// slower than the ego by more than its speed), empty when it can. Such a cell is infeasible.
  std::string infeasible{};
};

/// A lane of a family's road across its width, for the exports (an OpenDRIVE lane): its width, its
/// OpenDRIVE type ("driving", "shoulder", "sidewalk", ...), and whether its traffic comes the other
/// way. Listed from the road's right edge leftwards; the oncoming lanes, if any, last.
struct RoadLane {
  double width_m = 0.0;
  std::string type = "driving";
  bool oncoming = false;
};

/// A scenario family as the registry knows it.
struct ScenarioFamilyInfo {
  std::string name;         ///< as scene files name it: "tjunction"
  std::string description;  ///< one line, for `emrm families`
  /// The family's factors for a scene (their limits may depend on it: a passage no wider than the
  /// road). The first three are the ego's speed, the TTC and the friction (FactorTable).
  std::function<FactorTable(const SceneConfig&)> factors;
  /// The layout of one cell, for a cell that factors(config).validate() accepted.
  std::function<SceneLayout(const SceneConfig&, const CellInput&)> layout;
  /// Optional: a cheaper check of a cell with the same outcome as factors(config).validate(cell)
  /// (it runs for every cell simulated). Unset: the table's.
  std::function<void(const SceneConfig&, const CellInput&)> validate_cell = nullptr;
  /// Optional: the lanes of the road across its drivable width, for the exports (their widths add up
  /// to it). Unset: one driving lane over the whole width.
  std::function<std::vector<RoadLane>(const SceneConfig&)> lanes = nullptr;
  /// Optional: checks what a scene file's family settings name against what they name it in (an
  /// imported scenario's parameters and storyboard elements); throws core::ConfigError at the field.
  /// load_scene_config calls it, so the error names the scene file's line and column.
  std::function<void(const SceneConfig&)> check_scene = nullptr;
  /// Whether the results derived for the T-junction's geometry hold for this family: the
  /// unavoidability certificate (certificate.hpp), the exports and `assess`. Without the certificate
  /// a family's unavoidable cells stay `undecided`.
  bool tjunction_analytics = false;
  /// Whether the analytic stop boundary holds (stop_physics.hpp): the hazard's near side is v·TTC
  /// ahead of the ego's front at t = 0 and never comes closer, so braking straight through the
  /// actuators avoids it whenever it stops within v·TTC. False for a family whose TTC measures
  /// another gap (a cut-in's: the gap over the relative speed): its maps are then simulated cell by
  /// cell, and the stop boundary's checks, lines and tables are left out.
  bool stop_boundary = true;
};

/// Registers a family for as long as the object lives. Throws UsageError for a name already
/// registered, or a family without factors or layout.
class FamilyRegistration {
 public:
  explicit FamilyRegistration(ScenarioFamilyInfo info);
  ~FamilyRegistration();
  FamilyRegistration(const FamilyRegistration&) = delete;
  FamilyRegistration& operator=(const FamilyRegistration&) = delete;

 private:
  std::string name_;
};

/// The registered family of that name. Throws UsageError for an unknown name, listing the known ones.
[[nodiscard]] std::shared_ptr<const ScenarioFamilyInfo> find_family(std::string_view name);
/// The registered families' names, in registration order (the shipped ones first).
[[nodiscard]] std::vector<std::string> family_names();
/// The registered families, in registration order.
[[nodiscard]] std::vector<std::shared_ptr<const ScenarioFamilyInfo>> registered_families();
/// Whether the scene's family has the T-junction's geometry and analytics
/// (ScenarioFamilyInfo::tjunction_analytics): its certificate, its own road and scenario exports,
/// its recorded truck, its trajectory panels.
[[nodiscard]] bool has_tjunction_analytics(const SceneConfig& config);

/// The shipped T-junction family ("tjunction", sim/tjunction.cpp).
[[nodiscard]] ScenarioFamilyInfo tjunction_family();

}  // namespace emrm::sim
