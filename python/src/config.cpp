// emrm.Scene and its parts: the scene configuration (sim::SceneConfig, docs/scene-yaml.md) as
// read-only Python objects. Their attributes, to_dict() and repr() walk the structs' own
// serialize(), so every field the YAML has is there under its YAML name, and nothing else.

#include <pybind11/stl.h>

#include <string_view>
#include <type_traits>
#include <vector>

#include "bindings.hpp"
#include "emrm/core/enum_names.hpp"

namespace emrm::python {
namespace {

template <class T>
concept Config = requires(T& value, core::Validator& archive) {
  value.serialize(archive);
};

// An archive that hands every field serialize() names to `visit(key, value)`, in its order.
template <class Visit>
class FieldVisitor {
 public:
  static constexpr bool kReading = false;
  explicit FieldVisitor(Visit& visit) : visit_(visit) {}
  template <class T, class... Constraints>
  void required(std::string_view key, T& value, const Constraints&... /*checked by Validator*/) {
    visit_(key, value);
  }
  template <class T, class... Constraints>
  void optional(std::string_view key, T& value, const Constraints&... /*checked by Validator*/) {
    visit_(key, value);
  }
  void location(const SourceLocation& /*where*/) const noexcept {}
  template <class... Args>
  void ensure(bool /*ok*/, std::string_view /*field*/, std::string_view /*format*/, const Args&... /*args*/) const {}

 private:
  Visit& visit_;
};

template <Config T, class Visit>
void for_each_field(const T& config, Visit visit) {
  FieldVisitor<Visit> archive(visit);
  const_cast<T&>(config).serialize(archive);  // serialize() only reads fields when not reading
}

// A field as Python sees it: a part (a copy; parts are read-only) or a number, count or name (an
// enumeration by the name the YAML spells it).
template <class V>
py::object field_object(const V& value) {
  if constexpr (std::is_enum_v<V>)
    return py::str(std::string(core::enum_name(value)));
  else
    return py::cast(value, py::return_value_policy::copy);
}

template <class V>
struct IsPartList : std::false_type {};
template <Config T>
struct IsPartList<std::vector<T>> : std::true_type {};

template <Config T>
py::dict to_dict(const T& config) {
  py::dict dict;
  for_each_field(config, [&](std::string_view key, const auto& value) {
    using V = std::decay_t<decltype(value)>;
    if constexpr (Config<V>) {
      dict[py::str(key)] = to_dict(value);
    } else if constexpr (IsPartList<V>::value) {  // a list of parts: a list of dicts
      py::list parts;
      for (const auto& part : value) parts.append(to_dict(part));
      dict[py::str(key)] = parts;
    } else {
      dict[py::str(key)] = field_object(value);
    }
  });
  return dict;
}

template <Config T>
py::object field_named(const T& config, const std::string& name) {
  py::object found;
  for_each_field(config, [&](std::string_view key, const auto& value) {
    if (key == name) found = field_object(value);
  });
  return found;
}

template <Config T>
std::string repr(const T& config, const char* class_name) {
  std::string text = std::string(class_name) + "(";
  bool first = true;
  for_each_field(config, [&](std::string_view key, const auto& value) {
    text += (first ? "" : ", ") + std::string(key) + "=" + py::repr(field_object(value)).template cast<std::string>();
    first = false;
  });
  return text + ")";
}

// Adds one read-only attribute per field, to_dict(), == (by to_dict) and repr().
template <Config T, class... Options>
void add_fields(py::class_<T, Options...>& cls, const char* class_name) {
  std::vector<std::string> names;
  for_each_field(T{}, [&](std::string_view key, const auto& /*value*/) { names.emplace_back(key); });
  for (const std::string& name : names)
    cls.def_property_readonly(name.c_str(), [name](const T& self) { return field_named(self, name); });
  cls.def("to_dict", &to_dict<T>, "Every field as plain Python values, parts as nested dicts (YAML names).");
  cls.def("__eq__", [](const T& self, py::object other) {
    return py::isinstance<T>(other) && to_dict(self).equal(to_dict(other.cast<const T&>()));
  });
  cls.def("__repr__", [class_name](const T& self) { return repr(self, class_name); });
  cls.attr("__hash__") = py::none();
}

template <Config T>
void bind_part(py::module_& m, const char* name, const char* doc) {
  py::class_<T> cls(m, name, doc);
  add_fields(cls, name);
}

// `changes` merged into `base`: nested mappings merge, anything else replaces. A key may name a
// nested field as a path, "truck.speed_kph" or (as a keyword) truck__speed_kph.
void merge(const py::dict& base, py::handle changes) {
  for (const auto& [key, value] : py::dict(py::reinterpret_borrow<py::object>(changes))) {
    std::string path = py::str(key).cast<std::string>();
    for (std::size_t at = path.find("__"); at != std::string::npos; at = path.find("__")) path.replace(at, 2, ".");
    py::dict target = base;
    std::size_t start = 0;
    for (std::size_t dot = path.find('.'); dot != std::string::npos; start = dot + 1, dot = path.find('.', start)) {
      const py::str part(path.substr(start, dot - start));
      if (!target.contains(part) || !py::isinstance<py::dict>(target[part])) target[part] = py::dict();
      target = target[part];
    }
    const py::str last(path.substr(start));
    if (py::isinstance<py::dict>(value) && target.contains(last) && py::isinstance<py::dict>(target[last]))
      merge(target[last], value);
    else
      target[last] = value;
  }
}

std::shared_ptr<sim::SceneConfig> scene_from_mapping(py::handle mapping) {
  return parse_mapping(mapping, [](const std::string& text) {
    return std::make_shared<sim::SceneConfig>(sim::parse_scene_config(text, "<scene mapping>"));
  });
}

std::shared_ptr<sim::SceneConfig> load_scene(py::handle path, const std::optional<std::string>& profile) {
  const std::filesystem::path file = to_path(path);
  auto scene = std::make_shared<sim::SceneConfig>(sim::load_scene_config(file));
  if (profile) sim::apply_profile(*scene, *profile, file.parent_path());
  return scene;
}

const std::shared_ptr<const sim::SceneConfig>& built_in_scene() {
  static const auto scene = std::make_shared<const sim::SceneConfig>();
  return scene;
}

}  // namespace

std::shared_ptr<const sim::SceneConfig> scene_from(py::handle scene) {
  if (scene.is_none()) return built_in_scene();
  if (py::isinstance<sim::SceneConfig>(scene)) return scene.cast<std::shared_ptr<sim::SceneConfig>>();
  if (is_path(scene)) return load_scene(scene, std::nullopt);
  return scene_from_mapping(scene);
}

void bind_config(py::module_& m) {
  bind_part<sim::RoadConfig>(m, "RoadConfig", "The main road (docs/scene-yaml.md, `road:`).");
  bind_part<sim::ObstacleConfig>(m, "ObstacleConfig",
                                 "A body entering the road: the T-junction's truck (`truck:`), the highway's truck "
                                 "and deer (`highway.truck:`, `highway.deer:`), the street's parked car, pedestrian "
                                 "and oncoming car (`crossing.parked:`, ...).");
  m.attr("TruckConfig") = m.attr("ObstacleConfig");  // the T-junction's truck, by its earlier name
  bind_part<sim::VehicleParams>(m, "VehicleParams", "The ego car (`ego:`).");
  bind_part<sim::SimulationConfig>(m, "SimulationConfig", "Vehicle model, time step and horizon (`simulation:`).");
  bind_part<sim::ActuationConfig>(m, "ActuationConfig",
                                  "Perception latency, brake and steering actuators (`actuation:`).");
  bind_part<sim::SeverityConfig>(m, "SeverityConfig", "The impact and injury model (`severity:`).");
  bind_part<sim::PlannerConfig>(m, "PlannerConfig", "The RRT planners' budget (`planner:`).");
  bind_part<sim::ControllerConfig>(m, "ControllerConfig",
                                   "The EMRM controller's on-board planning budget (`controller:`).");
  bind_part<sim::RoadsideConfig>(m, "RoadsideConfig", "What lies beyond the road's edges (`roadside:`).");
  bind_part<sim::SafeStateConfig>(m, "SafeStateConfig", "When an avoidance counts: the safe state (`safe_state:`).");
  bind_part<sim::HighwayConfig>(
      m, "HighwayConfig", "The road and obstacles of the family highway_obstacle (`highway:`, docs/families.md).");
  bind_part<sim::CrossingConfig>(
      m, "CrossingConfig", "The street and actors of the family pedestrian_crossing (`crossing:`, docs/families.md).");
  bind_part<sim::CarBody>(m, "CarBody", "A car of the cut-in's traffic (`cut_in.cutting:`, `cut_in.follower:`).");
  bind_part<sim::CutInConfig>(m, "CutInConfig",
                              "The highway and cars of the family cut_in (`cut_in:`, docs/families.md).");
  bind_part<sim::ImportedFactor>(
      m, "ImportedFactor", "A declared parameter of an imported scenario that is a factor (`openscenario.factors`).");
  bind_part<sim::OpenScenarioConfig>(
      m, "OpenScenarioConfig",
      "The scenario of the family openscenario and how it is handed over (`openscenario:`, docs/import.md).");

  py::class_<sim::SceneConfig, std::shared_ptr<sim::SceneConfig>> scene(
      m, "Scene",
      "A scene (docs/scene-yaml.md): every field of scene.yaml as a read-only attribute under its\n"
      "YAML name. Scene() is the built-in scene, the one `emrm simulate` runs without --scene.");
  scene.def(py::init([] { return std::make_shared<sim::SceneConfig>(); }), "The built-in scene.");
  add_fields(scene, "Scene");
  scene.def_static(
      "load", &load_scene, py::arg("path"), py::arg("profile") = py::none(),
      "Loads a scene file, as `emrm simulate --scene FILE [--profile NAME|FILE]` does; a profile NAME is\n"
      "looked up in the profiles/ folder beside the file. Raises InputError at the file's line and column.");
  scene.def_static("from_dict", &scene_from_mapping, py::arg("mapping"),
                   "A scene from a mapping shaped like scene.yaml (missing fields keep their defaults). Raises\n"
                   "InputError for an unknown field, a wrong type or a value out of range.");
  scene.def(
      "with_",
      [](const sim::SceneConfig& self, const py::object& changes, const py::kwargs& more) {
        py::dict fields = to_dict(self);
        if (!changes.is_none()) merge(fields, changes);
        merge(fields, more);
        return scene_from_mapping(fields);
      },
      py::arg("changes") = py::none(), py::pos_only(),
      "A copy with some fields changed, checked as from_dict checks: scene.with_(truck={'speed_kph': 20}),\n"
      "scene.with_(truck__speed_kph=20) or scene.with_({'truck.speed_kph': 20}).");
  scene.def(
      "with_profile",
      [](const sim::SceneConfig& self, const std::string& profile) {
        auto copy = std::make_shared<sim::SceneConfig>(self);
        sim::apply_profile(*copy, profile, {});
        return copy;
      },
      py::arg("profile"),
      "A copy with an actuation profile overlaid (docs/actuation.md): a FILE, or a NAME in ./profiles/.");
  scene.def("to_yaml", &sim::to_yaml, "The effective scene as YAML, as reports print it.");
  scene.def(py::pickle([](const sim::SceneConfig& self) { return to_dict(self); },
                       [](const py::dict& fields) { return scene_from_mapping(fields); }));
}

}  // namespace emrm::python
