// An imported OpenSCENARIO scenario as the scenario family "openscenario" (family.hpp,
// docs/import.md "A scenario as a family").

#include "emrm/openscenario/family.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/core/trig.hpp"
#include "emrm/opendrive/road_network.hpp"
#include "emrm/openscenario/import.hpp"
#include "emrm/openscenario/player.hpp"
#include "emrm/openscenario/reader.hpp"
#include "emrm/sim/played.hpp"

namespace emrm::openscenario {
namespace {

// ---- what is read once per file -------------------------------------------------------------

// The scenario as its file declares it (no overrides), read once per file, ego and process.
std::shared_ptr<const Scenario> base_scenario(const std::string& file, const std::string& ego) {
  static std::mutex mutex;
  static std::map<std::pair<std::string, std::string>, std::shared_ptr<const Scenario>> read;
  const std::scoped_lock lock(mutex);
  auto& slot = read[{file, ego}];
  if (!slot) slot = std::make_shared<const Scenario>(load_openscenario(file, {.overrides = {}, .ego = ego}));
  return slot;
}

const Parameter* find_parameter(const Scenario& scenario, const std::string& name) {
  for (const Parameter& p : scenario.parameters)
    if (p.name == name) return &p;
  return nullptr;
}

// The ego's absolute speed in the Init (its first SpeedAction there), if it has one; const or not
// as the scenario is.
template <class S>
auto* init_speed(S& scenario, const std::string& ego) {
  using Speed = std::conditional_t<std::is_const_v<S>, const SpeedAction, SpeedAction>;
  for (auto& a : scenario.storyboard.init)
    if (a.actor == ego)
      if (Speed* speed = std::get_if<SpeedAction>(&a.kind); speed != nullptr && !speed->relative) return speed;
  return static_cast<Speed*>(nullptr);
}

// The unit of the attributes a parameter is ($name) when they all agree, else "1".
std::string unit_of(const Scenario& scenario, const std::string& parameter) {
  std::string unit;
  for (const ParameterUse& use : scenario.uses) {
    if (use.parameter != parameter || use.unit.empty()) continue;
    if (!unit.empty() && unit != use.unit) return "1";
    unit = use.unit;
  }
  return unit.empty() ? "1" : unit;
}

// Whether anything in the scenario refers to the parameter: an attribute, or another parameter's
// declared value (which may be used in turn). A parameter nothing refers to changes nothing.
bool referenced(const Scenario& scenario, const std::string& parameter) {
  for (const ParameterUse& use : scenario.uses)
    if (use.parameter == parameter) return true;
  for (const Parameter& p : scenario.parameters)
    for (const std::string_view name : parameter_references(p.default_text))
      if (name == parameter) return true;
  return false;
}

// ---- the scene's names ----------------------------------------------------------------------

// What the scene's openscenario block names must be in the scenario: its factors and speed
// parameter declared numbers, its hand-over a storyboard element.
void check_scene(const sim::SceneConfig& config) {
  const sim::OpenScenarioConfig& o = config.openscenario;
  const auto scenario = base_scenario(o.file, o.ego);
  const auto fail = [](core::FieldPath path, std::string detail) {
    throw core::ConfigError("scene", std::move(path), std::move(detail));
  };
  std::vector<std::string> numbers;
  for (const Parameter& p : scenario->parameters)
    if (numeric(p.type)) numbers.push_back(p.name);
  const auto check_number = [&](const std::string& name, core::FieldPath path) {
    if (std::find(numbers.begin(), numbers.end(), name) == numbers.end())
      fail(std::move(path),
           fmt::format("'{}' is no numeric parameter {} declares (it declares {})", name,
                       scenario->file.filename().string(),
                       numbers.empty() ? std::string("none") : fmt::format("{}", fmt::join(numbers, ", "))));
  };
  if (!o.speed_parameter.empty())
    check_number(o.speed_parameter, {{std::string("openscenario"), std::string("speed_parameter")}});
  for (std::size_t i = 0; i < o.factors.size(); ++i)
    check_number(o.factors[i].parameter,
                 {{std::string("openscenario"), std::string("factors"), i, std::string("parameter")}});
  if (!o.handover.empty()) {
    const std::vector<std::string> names = scenario->element_names();
    if (std::find(names.begin(), names.end(), o.handover) == names.end())
      fail(
          {{std::string("openscenario"), std::string("handover")}},
          fmt::format("'{}' is no storyboard element of {} (it has {})", o.handover, scenario->file.filename().string(),
                      names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "))));
  }
}

// ---- factors --------------------------------------------------------------------------------

constexpr double kDefaultSpeed_kph = 50.0;  // without a scenario, or an ego without an Init speed
constexpr double kDefaultTtc_s = 1.5;

sim::FactorTable scenario_factors(const sim::SceneConfig& config) {
  const sim::OpenScenarioConfig& o = config.openscenario;
  // Without a scenario (`emrm families`): the method's factors; a scenario adds its own.
  if (o.file.empty()) return sim::FactorTable(sim::method_factors(kDefaultSpeed_kph, kDefaultTtc_s, 1.0));
  const auto scenario = base_scenario(o.file, o.ego);
  const SpeedAction* init = init_speed(*scenario, o.ego);
  double speed_kph = init != nullptr ? init->value * sim::kKphPerMps : 0.0;
  if (!o.speed_parameter.empty())
    if (const Parameter* p = find_parameter(*scenario, o.speed_parameter))
      speed_kph = std::stod(p->value) * sim::kKphPerMps;
  std::vector<sim::Factor> factors =
      sim::method_factors(speed_kph > 0.0 ? speed_kph : kDefaultSpeed_kph, kDefaultTtc_s, 1.0);
  for (const sim::ImportedFactor& f : o.factors) {
    const Parameter* p = find_parameter(*scenario, f.parameter);
    const double value = p != nullptr && numeric(p->type) ? std::stod(p->value) : 0.0;
    factors.push_back({.key = f.parameter,
                       .unit = f.unit,
                       .what = "parameter " + f.parameter,
                       .axis = f.unit == "1" ? f.parameter : fmt::format("{} ({})", f.parameter, f.unit),
                       .plural = f.parameter,
                       .held = f.parameter + " = {}",
                       .brief = f.parameter + " {:g}",
                       .default_value = value,
                       .limits = {.low = f.min.value_or(-std::numeric_limits<double>::infinity()),
                                  .low_inclusive = true,
                                  .high = f.max.value_or(std::numeric_limits<double>::infinity())},
                       .name = f.parameter});
  }
  return sim::FactorTable(std::move(factors));
}

// ---- a cell's layout ------------------------------------------------------------------------

// The box's centre of an entity whose reference point is at `s`.
sim::Track::Sample box_centre(const Sample& s, const BoundingBox& box) {
  const core::Vec2 along = core::Vec2::unit(s.heading_rad);
  const core::Vec2 across{-along.y, along.x};
  const core::Vec2 c = core::Vec2{s.x_m, s.y_m} + along * box.center_x_m + across * box.center_y_m;
  return {c.x, c.y, s.heading_rad, std::abs(s.speed_mps)};
}

sim::ActorKind kind_of(const Entity& e) {
  if (e.kind == EntityKind::kPedestrian)
    return e.category == "animal" ? sim::ActorKind::kAnimal : sim::ActorKind::kPedestrian;
  if (e.kind == EntityKind::kMiscObject) return sim::ActorKind::kStaticObject;
  if (e.category == "truck" || e.category == "bus" || e.category == "semitrailer" || e.category == "trailer")
    return sim::ActorKind::kTruck;
  if (e.category == "bicycle" || e.category == "motorbike") return sim::ActorKind::kCyclist;
  return sim::ActorKind::kCar;
}

// An actor's mass when its entity gives none (or 0) (kg): a car's, a truck's, a rider's with the
// bicycle, a walker's, a deer's; a misc object without one is immovable (ActorBody: a mass of 0).
double default_mass_kg(sim::ActorKind kind) {
  switch (kind) {
    case sim::ActorKind::kTruck:
      return 12000.0;
    case sim::ActorKind::kCyclist:
      return 90.0;
    case sim::ActorKind::kPedestrian:
      return 75.0;
    case sim::ActorKind::kAnimal:
      return 70.0;
    case sim::ActorKind::kStaticObject:
      return 0.0;
    case sim::ActorKind::kCar:
      break;
  }
  return 1500.0;
}

sim::PlayedScenario played_of(const Scenario& scenario, const Trajectories& trajectories, const std::string& ego,
                              double dt_s) {
  sim::PlayedScenario out;
  out.dt_s = dt_s;
  for (const Entity& e : scenario.entities) {
    const auto it = trajectories.find(e.name);
    if (it == trajectories.end()) continue;
    sim::PlayedUser user;
    const sim::ActorKind kind = kind_of(e);
    const double mass_kg = e.mass_kg.value_or(default_mass_kg(kind));
    // A uniform box's yaw inertia, m (l² + w²) / 12.
    const double inertia_kgm2 = mass_kg * (e.box.length_m * e.box.length_m + e.box.width_m * e.box.width_m) / 12.0;
    user.body = {kind, e.box.length_m, e.box.width_m, mass_kg, inertia_kgm2, e.name};
    for (const Sample& s : it->second) user.path.push_back(box_centre(s, e.box));
    if (e.name == ego)
      out.ego = std::move(user);
    else
      out.others.push_back(std::move(user));
  }
  return out;
}

// The drivable band across a straight road at s: the lanes a car may use (in normal driving or to
// avoid harm) next to the one at t = `ego_t`, outwards until one it may not; its lowest and highest t.
std::optional<std::pair<double, double>> band_at(const opendrive::Road& road, double s, double ego_t) {
  const std::optional<int> ego_lane = road.lane_at(s, ego_t);
  if (!ego_lane) return std::nullopt;
  const std::vector<int> ids = road.lane_ids(s);  // leftmost first, 0 included
  const auto here = std::find(ids.begin(), ids.end(), *ego_lane);
  const auto usable = [&](int id) {
    return id == 0 || opendrive::info(road.lane_type(id, s)).drivability != opendrive::Drivability::kNotDrivable;
  };
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  const auto cover = [&](int id) {
    const auto [inner, outer] = road.lane_borders(id, s);
    low = std::min({low, inner, outer});
    high = std::max({high, inner, outer});
  };
  cover(*ego_lane);
  for (auto it = here; it != ids.begin() && usable(*std::prev(it));) cover(*--it);
  for (auto it = std::next(here); it != ids.end() && usable(*it); ++it) cover(*it);
  return std::pair{low, high};
}

constexpr double kStraight_m = 0.02;     // the reference line's most lateral deviation from a line
constexpr double kStraight_rad = 0.005;  // and its heading's from the line's
constexpr double kBehind_m = 20.0;       // the stretch checked behind the ego
constexpr double kStretchStep_m = 1.0;

// The straight road the ego drives at the onset, in the ego's direction, with the narrowest
// drivable band over the stretch it may reach; or why there is none.
std::variant<sim::StraightRoad, std::string> straight_road(const opendrive::RoadNetwork& network,
                                                           const sim::Track::Sample& ego, double reach_m,
                                                           const sim::OpenScenarioConfig& o) {
  const auto at = network.world_to_road(ego.x_m, ego.y_m);
  if (!at) return std::string("the ego is on no road at the threat onset");
  const opendrive::Road& road = *at->road;
  const bool along = std::abs(core::wrap_angle(ego.heading_rad - at->heading)) <= std::numbers::pi / 2.0;
  const double s_from = std::max(0.0, at->s - (along ? kBehind_m : reach_m));
  const double s_to = std::min(road.length, at->s + (along ? reach_m : kBehind_m));
  const opendrive::Pose origin = road.to_world(at->s, 0.0);
  const core::Vec2 dir = core::Vec2::unit(origin.heading);
  const core::Vec2 normal{-dir.y, dir.x};
  double low = -std::numeric_limits<double>::infinity();
  double high = -low;
  for (double s = s_from;; s = std::min(s + kStretchStep_m, s_to)) {
    const opendrive::Pose p = road.to_world(s, 0.0);
    const double off = (core::Vec2{p.x, p.y} - core::Vec2{origin.x, origin.y}).dot(normal);
    if (std::abs(off) > kStraight_m || std::abs(core::wrap_angle(p.heading - origin.heading)) > kStraight_rad)
      return fmt::format(
          "road {} is not straight where the ego may drive (at s = {:.1f} m it is {:.2f} m and {:.2f}° off the line "
          "at s = {:.1f} m): emrm lays imported scenes out on straight roads",
          road.id, s, off, core::wrap_angle(p.heading - origin.heading) * 180.0 / std::numbers::pi, at->s);
    const auto band = band_at(road, s, at->t);
    if (!band) return fmt::format("the ego's lane on road {} ends at s = {:.1f} m, within its reach", road.id, s);
    low = std::max(low, band->first);
    high = std::min(high, band->second);
    if (s >= s_to) break;
  }
  sim::StraightRoad out{{origin.x, origin.y}, origin.heading, {}};
  out.band.right = o.right_roadside;
  out.band.left = o.left_roadside;
  out.band.min_y_m = low;
  out.band.max_y_m = high;
  if (!along) {  // the ego drives against s: the road frame turns round
    out.heading_rad = core::wrap_angle(origin.heading + std::numbers::pi);
    out.band.min_y_m = -high;
    out.band.max_y_m = -low;
  }
  return out;
}

// Plays the scenario for one cell and lays it out.
sim::SceneLayout play_cell(const sim::SceneConfig& config, const sim::CellInput& cell) {
  const sim::OpenScenarioConfig& o = config.openscenario;
  const auto base = base_scenario(o.file, o.ego);
  ParameterOverrides overrides;
  for (std::size_t i = 0; i < o.factors.size(); ++i)
    overrides[o.factors[i].parameter] = fmt::format("{:.17g}", cell[sim::kMethodFactors + i]);
  const double speed_mps = cell.ego_speed_kph() / sim::kKphPerMps;
  if (!o.speed_parameter.empty()) overrides[o.speed_parameter] = fmt::format("{:.17g}", speed_mps);
  const double horizon_s = config.simulation.horizon_s;
  PlayOptions options;
  options.dt_s = config.simulation.dt_s;
  options.duration_s = o.onset_search_s + horizon_s + 1.0;
  std::optional<std::size_t> armed;  // the step the hand-over element starts in
  if (!o.handover.empty())
    options.element_started = [&](double t_s, const std::string& element) {
      if (!armed && element == o.handover) armed = static_cast<std::size_t>(std::llround(t_s / options.dt_s));
    };
  Scenario scenario;
  sim::PlayedScenario played;
  try {
    scenario = overrides.empty() ? *base : load_openscenario(o.file, {.overrides = overrides, .ego = o.ego});
    if (o.speed_parameter.empty())
      if (SpeedAction* speed = init_speed(scenario, o.ego)) speed->value = speed_mps;
    played = played_of(scenario, play(scenario, options), o.ego, options.dt_s);
  } catch (const InputError& e) {
    // The storyboard does not read or play with this cell's values (a parameter that makes a
    // duration negative, a lane change to a lane that is not there): the cell is infeasible, laid
    // out as the scenario's declared values play, and the sweep goes on.
    options.element_started = nullptr;
    sim::SceneLayout out = sim::layout_from_onset(played_of(*base, play(*base, options), o.ego, options.dt_s), {}, {},
                                                  config.ego.length_m);
    out.infeasible = fmt::format("the scenario does not play with this cell's values: {}", e.what());
    return out;
  }
  if (!o.handover.empty() && !armed) {
    sim::SceneLayout out = sim::layout_from_onset(played, {}, {}, config.ego.length_m);
    out.infeasible = fmt::format(
        "the storyboard element '{}' (openscenario.handover) does not start over the scenario's first {:g} s",
        o.handover, options.duration_s);
    return out;
  }
  // The hand-over: at the named element's start, else where the TTC first falls to the cell's.
  const auto onset =
      armed ? std::optional(sim::onset_at(played, *armed, config.ego.length_m, config.ego.width_m))
            : sim::threat_onset(played, cell.time_to_collision_s(), config.ego.length_m, config.ego.width_m);
  const sim::Track::Sample& ego = played.ego.path.at(onset ? onset->step : 0);
  const double reach_m = ego.speed_mps * horizon_s + config.ego.length_m;
  const auto road = scenario.network ? straight_road(*scenario.network, ego, reach_m, o)
                                     : std::variant<sim::StraightRoad, std::string>(
                                           std::string("the scenario has no road network (RoadNetwork/LogicFile)"));
  if (const auto* why = std::get_if<std::string>(&road)) {
    sim::SceneLayout out = sim::layout_from_onset(played, {}, onset, config.ego.length_m);
    out.infeasible = *why;
    return out;
  }
  return sim::layout_from_onset(
      played, std::get<sim::StraightRoad>(road), onset, config.ego.length_m,
      fmt::format("the ego's time to collision with every other road user stays above {:g} s over the scenario's "
                  "first {:g} s (openscenario.onset_search_s)",
                  cell.time_to_collision_s(), o.onset_search_s));
}

// The layouts of the last cells: a cell is laid out several times (simulate, verify, the exports),
// and each time plays the scenario.
sim::SceneLayout layout_of(const sim::SceneConfig& config, const sim::CellInput& cell) {
  static std::mutex mutex;
  static std::deque<std::pair<std::string, sim::SceneLayout>> recent;
  constexpr std::size_t kKept = 64;
  const std::string key = sim::to_yaml(config) + fmt::format("{}", fmt::join(cell, "|"));
  {
    const std::scoped_lock lock(mutex);
    for (const auto& [k, layout] : recent)
      if (k == key) return layout;
  }
  sim::SceneLayout layout = play_cell(config, cell);
  const std::scoped_lock lock(mutex);
  recent.emplace_back(key, layout);
  if (recent.size() > kKept) recent.pop_front();
  return layout;
}

}  // namespace

sim::ScenarioFamilyInfo scenario_family() {
  return {.name = "openscenario",
          .description =
              "a scenario imported from ASAM OpenSCENARIO with its OpenDRIVE road (emrm import): its "
              "declared parameters as factors, the threat onset at the cell's TTC",
          .factors = scenario_factors,
          .layout = layout_of,
          .check_scene = check_scene,
          .tjunction_analytics = false,
          .stop_boundary = false};
}

sim::SceneConfig scene_of(const std::filesystem::path& file, const ImportChoices& choices) {
  const std::string path = std::filesystem::absolute(file).lexically_normal().string();
  // The reader chooses the ego (--ego, else default_ego) and refuses a name that is no entity.
  const auto scenario = base_scenario(path, choices.ego);
  sim::SceneConfig config;
  config.name = scenario->file.stem().string();
  config.family = "openscenario";
  config.openscenario.file = path;
  const Entity* ego = scenario->find_entity(scenario->ego);
  if (ego == nullptr || ego->kind != EntityKind::kVehicle)
    throw InputError(ego != nullptr ? ego->where : SourceLocation{path, 0, 0},
                     "the ego must be a Vehicle of the scenario (name it with --ego)");
  config.openscenario.ego = ego->name;
  config.ego.length_m = ego->box.length_m;
  config.ego.width_m = ego->box.width_m;
  if (ego->mass_kg) config.ego.mass_kg = *ego->mass_kg;
  // The parameter the ego's Init speed is ($name): the factor speed_kph sets it.
  if (const SpeedAction* init = init_speed(*scenario, ego->name); init != nullptr && !init->parameter.empty())
    if (const Parameter* p = find_parameter(*scenario, init->parameter); p != nullptr && numeric(p->type))
      config.openscenario.speed_parameter = p->name;
  std::vector<std::string> numeric_parameters;  // those --factors may name
  std::vector<std::string> used;                // the default: those the scenario refers to
  for (const Parameter& p : scenario->parameters)
    if (numeric(p.type)) {
      numeric_parameters.push_back(p.name);
      if (referenced(*scenario, p.name)) used.push_back(p.name);
    }
  if (choices.factors.empty()) {
    numeric_parameters = used;
  } else {
    for (const std::string& name : choices.factors)
      if (std::find(numeric_parameters.begin(), numeric_parameters.end(), name) == numeric_parameters.end())
        throw InputError({path, 0, 0}, fmt::format("--factors: '{}' is no numeric parameter the scenario declares "
                                                   "(it declares {})",
                                                   name, fmt::join(numeric_parameters, ", ")));
    numeric_parameters = choices.factors;
  }
  std::erase(numeric_parameters, config.openscenario.speed_parameter);  // speed_kph is it
  if (numeric_parameters.size() > sim::kMaxImportedFactors)
    throw InputError(
        {path, 0, 0},
        fmt::format("the scenario uses {} numeric parameters ({}); a scene makes at most {} of them "
                    "factors: choose those you vary with `emrm import --factors A,B,...`",
                    numeric_parameters.size(), fmt::join(numeric_parameters, ", "), sim::kMaxImportedFactors));
  for (const std::string& name : numeric_parameters)
    config.openscenario.factors.push_back({.parameter = name, .unit = unit_of(*scenario, name), .min = {}, .max = {}});
  try {
    sim::validate(config);
  } catch (const InputError& e) {  // the ego's footprint does not fit the car emrm drives
    throw InputError(ego->where, fmt::format("the ego '{}' cannot be the car emrm drives: {} (choose the ego with "
                                             "--ego, or write a scene file with an ego: block of its own)",
                                             ego->name, e.message()));
  }
  return config;
}

Registration::Registration()
    : family_(scenario_family()),
      reader_(".xosc", [](const std::filesystem::path& file) { return import_scenario(file).scene; }) {}

}  // namespace emrm::openscenario
