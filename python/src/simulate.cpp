// emrm.simulate: one cell under every strategy (sim::simulate_cell, docs/simulate.md), with the GIL
// released while it runs. The result keeps the library's CellResult as it is: its fields are those
// of `emrm simulate --json` (sim::to_json, read on first use), its trajectories NumPy arrays over the
// result's own memory.

#include "emrm/sim/simulate.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "emrm/sim/json.hpp"

namespace emrm::python {
namespace {

// A simulated cell and what Python has asked of it. Only touched with the GIL held.
struct SimulatedCell {
  std::shared_ptr<const sim::SceneConfig> scene;  // shared with the emrm.Scene given, never copied
  sim::CellResult result;
  std::uint64_t seed = 1;
  bool timing = false;
  std::optional<py::dict> fields;           // the JSON without trajectories, as Python objects; made on first use
  std::vector<std::vector<double>> speeds;  // per strategy: the ego's speed, on first use
  std::vector<std::vector<std::array<double, 3>>> trucks;  // per strategy: the truck's x, y, heading

  [[nodiscard]] nlohmann::json json(bool trajectories) const {
    return sim::to_json(result, sim::Scene(*scene, result.input), seed, {timing, trajectories});
  }
  const py::dict& field_dict() {
    if (!fields) fields = py::dict(to_python(json(false)));
    return *fields;
  }
};
using CellPtr = std::shared_ptr<SimulatedCell>;

struct OutcomeView {
  CellPtr cell;
  std::size_t index = 0;
  [[nodiscard]] const sim::StrategyOutcome& outcome() const { return cell->result.strategies[index]; }
};

struct TrajectoryView {
  CellPtr cell;
  std::size_t index = 0;
  bool truck = false;
  [[nodiscard]] const std::vector<sim::PathPoint>& path() const { return cell->result.strategies[index].path; }
};

// Keys `emrm simulate --json` writes only for some cells or strategies: None when absent.
const std::vector<std::string> kOptionalCellKeys{"evidence", "mitigation_evidence", "strengthened", "harm_reduction",
                                                 "certificate"};
const std::vector<std::string> kOptionalOutcomeKeys{"loss_evaluation_trace", "chosen_strategy", "adopted_from"};

py::object member(const py::dict& fields, const std::string& name, const std::vector<std::string>& optional) {
  if (fields.contains(name)) return fields[py::str(name)];
  if (std::find(optional.begin(), optional.end(), name) != optional.end()) return py::none();
  throw py::attribute_error(name);
}

// dir(): the class's own attributes and the JSON's keys, for completion.
py::list names(py::handle self, const py::dict& fields, const std::vector<std::string>& optional) {
  const py::module_ builtins = py::module_::import("builtins");
  py::set out(builtins.attr("object").attr("__dir__")(self));
  for (const auto& [key, value] : fields) out.add(key);
  for (const auto& name : optional) out.add(name);
  return builtins.attr("sorted")(out);
}

// A read-only array of `count` doubles `stride` bytes apart from `first`, over memory `base` keeps.
py::array column(const double* first, std::size_t count, std::size_t stride, py::handle base) {
  static const double kNone = 0.0;
  py::array a(py::dtype::of<double>(), {count}, {stride}, count > 0 ? first : &kNone, base);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

const std::vector<std::string> kEgoColumns{"t", "x", "y", "psi", "v", "vx", "vy", "yaw_rate", "steer"};
const std::vector<std::string> kTruckColumns{"t", "x", "y", "psi"};

// The column `name`; a name the trajectory has not raises KeyError (or AttributeError, as an attribute).
py::array trajectory_column(const py::object& self, const std::string& name, bool attribute = false) {
  auto& view = self.cast<TrajectoryView&>();
  const auto& columns = view.truck ? kTruckColumns : kEgoColumns;
  if (std::find(columns.begin(), columns.end(), name) == columns.end()) {
    if (attribute) throw py::attribute_error(name);
    throw py::key_error(name);
  }
  SimulatedCell& cell = *view.cell;
  const auto& path = view.path();
  const std::size_t n = path.size();
  if (n == 0) return column(nullptr, 0, sizeof(double), self);
  constexpr std::size_t kPoint = sizeof(sim::PathPoint);
  const sim::PathPoint* p = path.data();
  if (name == "t") return column(&p->t_s, n, kPoint, self);
  if (view.truck) {
    // The truck where sim::to_json puts it: Scene::hazard_at at each of the ego's times.
    cell.trucks.resize(cell.result.strategies.size());
    auto& truck = cell.trucks[view.index];
    if (truck.size() != n) {
      const sim::Scene scene(*cell.scene, cell.result.input);
      truck.clear();
      for (const auto& point : path) {
        const sim::ActorState state = scene.hazard_at(point.t_s);
        truck.push_back({state.box.center.x, state.box.center.y, state.box.heading_rad});
      }
    }
    constexpr std::size_t kSample = sizeof(std::array<double, 3>);
    const double* first = truck.front().data();
    if (name == "x") return column(first, n, kSample, self);
    if (name == "y") return column(first + 1, n, kSample, self);
    if (name == "psi") return column(first + 2, n, kSample, self);
  } else {
    if (name == "x") return column(&p->state.x_m, n, kPoint, self);
    if (name == "y") return column(&p->state.y_m, n, kPoint, self);
    if (name == "psi") return column(&p->state.yaw_rad, n, kPoint, self);
    if (name == "vx") return column(&p->state.vx_mps, n, kPoint, self);
    if (name == "vy") return column(&p->state.vy_mps, n, kPoint, self);
    if (name == "yaw_rate") return column(&p->state.yaw_rate_radps, n, kPoint, self);
    if (name == "steer") return column(&p->state.steer_rad, n, kPoint, self);
    if (name == "v") {
      cell.speeds.resize(cell.result.strategies.size());
      auto& speed = cell.speeds[view.index];
      if (speed.size() != n) {
        speed.clear();
        for (const auto& point : path) speed.push_back(point.state.speed_mps());
      }
      return column(speed.data(), n, sizeof(double), self);
    }
  }
  throw py::key_error(name);  // not reached: every column of the lists is served above
}

// The strategies a `strategy` argument asks for; nothing for all of them (CellOptions' default).
std::optional<std::vector<std::string>> strategies_asked(py::handle strategy) {
  if (strategy.is_none()) return std::nullopt;
  std::vector<std::string> names;
  if (py::isinstance<py::str>(strategy))
    names.push_back(strategy.cast<std::string>());
  else
    for (py::handle name : strategy) names.push_back(py::str(name).cast<std::string>());
  if (names.empty()) throw UsageError("emrm.simulate: strategy: expected a name, a list of names or 'all', got none");
  if (std::find(names.begin(), names.end(), "all") != names.end()) return std::nullopt;
  for (const auto& name : names) sim::validate_strategy(name);
  return names;
}

// The cell the keywords name: the scene's defaults overlaid with the factors given by their keys
// (sim::scenario_factors), the ego speed and the TTC required, as `emrm simulate` has them.
sim::CellInput cell_from(const sim::SceneConfig& scene, const py::kwargs& given) {
  const sim::FactorTable factors = sim::scenario_factors(scene);
  sim::CellInput cell = factors.defaults();
  for (const auto& [key, value] : given) {
    const std::string name = py::str(key);
    const auto i = factors.find(name);
    if (!i)
      throw UsageError(
          fmt::format("emrm.simulate: the scene has no factor '{}' (its factors: {})", name, factors.key_list()));
    const sim::Factor& factor = factors[*i];
    // A categorical factor by its level's name (obstacle="deer"), every factor by a number.
    if (factor.categorical() && py::isinstance<py::str>(value)) {
      cell[*i] = factor.parse(value.cast<std::string>());
      continue;
    }
    try {
      cell[*i] = value.cast<double>();
    } catch (const py::cast_error&) {
      throw py::type_error(fmt::format("emrm.simulate: {} must be {}, not {}", name,
                                       factor.categorical() ? "a level's name or a number" : "a number",
                                       py::str(py::type::of(value).attr("__name__")).cast<std::string>()));
    }
  }
  for (const std::size_t required : {sim::kEgoSpeedFactor, sim::kTtcFactor})
    if (!given.contains(factors[required].key))
      throw UsageError(fmt::format("emrm.simulate: {} is required (a keyword)", factors[required].key));
  return cell;
}

CellPtr simulate(py::handle scene_arg, py::handle strategy, std::uint64_t seed, bool certify, bool timing,
                 const py::kwargs& factors) {
  auto cell = std::make_shared<SimulatedCell>();
  cell->scene = scene_from(scene_arg);
  cell->seed = seed;
  cell->timing = timing;
  const sim::CellInput input = cell_from(*cell->scene, factors);
  sim::CellOptions options;
  if (auto asked = strategies_asked(strategy)) options.strategies = std::move(*asked);
  options.seed = seed;
  options.certify = certify;
  {
    const py::gil_scoped_release release;
    cell->result = sim::simulate_cell(*cell->scene, input, options);
  }
  return cell;
}

}  // namespace

void bind_simulate(py::module_& m) {
  py::class_<TrajectoryView> trajectory(
      m, "Trajectory",
      "A strategy's executed trajectory at every integration step from t = 0, as read-only NumPy arrays\n"
      "over the result's own memory (no copy): t (s), x, y (m), psi (rad), v (m/s), and for the ego also\n"
      "vx, vy (m/s, body frame), yaw_rate (rad/s) and steer (rad). Strided views into the simulator's\n"
      "array of samples; the truck's at the same times, computed once on first use.");
  trajectory.def("__len__", [](const TrajectoryView& self) { return self.path().size(); });
  trajectory.def_property_readonly("columns", [](const TrajectoryView& self) {
    return py::tuple(py::cast(self.truck ? kTruckColumns : kEgoColumns));
  });
  trajectory.def(
      "__getitem__", [](const py::object& self, const std::string& name) { return trajectory_column(self, name); },
      py::arg("column"));
  for (const auto& name : kEgoColumns)
    trajectory.def_property_readonly(name.c_str(),
                                     [name](const py::object& self) { return trajectory_column(self, name, true); });
  trajectory.def(
      "to_dataframe",
      [](const py::object& self) {
        const auto& view = self.cast<const TrajectoryView&>();
        py::dict columns;
        for (const auto& name : view.truck ? kTruckColumns : kEgoColumns)
          columns[py::str(name)] = trajectory_column(self, name);
        return py::module_::import("pandas").attr("DataFrame")(columns);
      },
      "The columns as a pandas DataFrame (pandas copies them).");
  trajectory.def("__repr__", [](const TrajectoryView& self) {
    return std::string(self.truck ? "TruckTrajectory(" : "Trajectory(") +
           self.cell->result.strategies[self.index].strategy + ", " + std::to_string(self.path().size()) + " samples)";
  });

  py::class_<OutcomeView> outcome(
      m, "Outcome",
      "One strategy's outcome: every key of `emrm simulate --json`'s strategies.NAME as an attribute\n"
      "(docs/simulate.md), trajectory and truck_trajectory as Trajectory arrays.");
  // What a loop over many cells reads most, straight from the result (the other keys come from the JSON).
  outcome.def_property_readonly("strategy", [](const OutcomeView& self) { return self.outcome().strategy; });
  outcome.def_property_readonly("avoided", [](const OutcomeView& self) { return self.outcome().avoided; });
  outcome.def_property_readonly("loss_level", [](const OutcomeView& self) { return self.outcome().impact.loss_level; });
  outcome.def_property_readonly("trajectory", [](const OutcomeView& self) {
    return TrajectoryView{self.cell, self.index, false};
  });
  outcome.def_property_readonly("truck_trajectory", [](const OutcomeView& self) {
    return TrajectoryView{self.cell, self.index, true};
  });
  const auto outcome_fields = [](const OutcomeView& self) -> py::dict {
    return self.cell->field_dict()["strategies"][py::str(self.outcome().strategy)];
  };
  outcome.def("__getattr__", [outcome_fields](const OutcomeView& self, const std::string& name) {
    return member(outcome_fields(self), name, kOptionalOutcomeKeys);
  });
  outcome.def("__dir__", [outcome_fields](const py::object& self) {
    return names(self, outcome_fields(self.cast<const OutcomeView&>()), kOptionalOutcomeKeys);
  });
  outcome.def(
      "to_dict", [outcome_fields](const OutcomeView& self) { return py::dict(outcome_fields(self)); },
      "The keys of simulate --json's strategies.NAME but the two trajectories.");
  outcome.def("__repr__", [](const OutcomeView& self) {
    const auto& o = self.outcome();
    return "Outcome(" + o.strategy + ", avoided=" + (o.avoided ? "True" : "False") +
           ", loss_level=" + std::to_string(o.impact.loss_level) + ")";
  });

  py::class_<SimulatedCell, CellPtr> result(
      m, "CellResult",
      "One simulated cell: every key of `emrm simulate --json` as an attribute (docs/simulate.md): input,\n"
      "feasible, region, evidence, mitigation_evidence, strengthened, harm_reduction, certificate,\n"
      "unmitigated, strategies (name -> Outcome, in evaluation order), family, actors, road. Keys the JSON\n"
      "leaves out for a cell read None.");
  result.def_property_readonly("feasible", [](const SimulatedCell& self) { return self.result.feasible; });
  result.def_property_readonly("region",
                               [](const SimulatedCell& self) { return sim::region_name(self.result.region); });
  result.def_property_readonly("strategies", [](const CellPtr& self) {
    py::dict out;
    for (std::size_t i = 0; i < self->result.strategies.size(); ++i)
      out[py::str(self->result.strategies[i].strategy)] = OutcomeView{self, i};
    return out;
  });
  // The actors with their trajectories, as the JSON has them (the other keys' dictionary leaves
  // trajectories out).
  result.def_property_readonly(
      "actors", [](const SimulatedCell& self) { return to_python(self.json(true)["actors"]); },
      "Every actor (the hazard first): name, kind, length_m, width_m, mass_kg and trajectory, a list of\n"
      "{t, x, y, psi} at every simulation step.");
  result.def("__getattr__", [](SimulatedCell& self, const std::string& name) {
    return member(self.field_dict(), name, kOptionalCellKeys);
  });
  result.def("__dir__", [](const py::object& self) {
    return names(self, self.cast<SimulatedCell&>().field_dict(), kOptionalCellKeys);
  });
  result.def(
      "to_json", [](const SimulatedCell& self, int indent) { return self.json(true).dump(indent); },
      py::arg("indent") = 2, "The text `emrm simulate --json` prints (without its final line break).");
  result.def(
      "to_dict", [](const SimulatedCell& self) { return to_python(self.json(true)); },
      "simulate --json as Python objects, trajectories as lists of dicts.");
  result.def("__repr__", [](const SimulatedCell& self) {
    const auto& in = self.result.input;
    return "CellResult(" +
           py::repr(py::tuple(py::cast(std::vector<double>(in.begin(), in.end())))).cast<std::string>() +
           ", region=" + std::string(sim::region_name(self.result.region)) + ")";
  });

  m.def("simulate", &simulate, py::arg("scene") = py::none(), py::kw_only(), py::arg("strategy") = py::none(),
        py::arg("seed") = 1, py::arg("certify") = true, py::arg("timing") = false,
        "Simulates one cell under every strategy, as `emrm simulate` does (docs/simulate.md), with the GIL\n"
        "released. scene: an emrm.Scene, a scene file, a mapping, or None for the built-in scene; the\n"
        "cell's factors as keywords named by their keys (speed_kph=60, ttc_s=0.8, mu=...: the scene's\n"
        "factors, the ego speed and the TTC required, the others the scene's defaults when left out);\n"
        "strategy: a name, a list of names, None or 'all';\n"
        "certify=False searches cells a certificate proves unavoidable (--no-certify); timing adds the\n"
        "planners' wall-clock times (--timing). Raises InputError or UsageError for bad input.");
  m.def("strategy_names", &sim::strategy_names, "The registered strategies in evaluation order.");
}

}  // namespace emrm::python
