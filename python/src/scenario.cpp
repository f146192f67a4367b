// Covering arrays (`emrm ca`, docs/covering-arrays.md) and the minimum scenario set (`emrm plan`,
// docs/plan.md), each through the calls the command line makes, in its order.

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <chrono>
#include <optional>
#include <span>

#include "bindings.hpp"
#include "emrm/core/text.hpp"
#include "emrm/scenario/coverage.hpp"
#include "emrm/scenario/covering_array.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/pict_model.hpp"
#include "emrm/scenario/plan.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/workflow/plan_checks.hpp"
#include "emrm/workflow/safety_case.hpp"

namespace emrm::python {
namespace {

// ---- covering arrays -----------------------------------------------------------------------

// What a `constraints` argument becomes: a Python function of a row (level indices, -1 where not yet
// chosen) that is true when the row breaks a constraint, or PICT constraints over factors named
// p1, p2, … whose values are the level indices 0, 1, … (the header `emrm ca --levels` prints).
struct Constraints {
  std::optional<scenario::PictModel> model;  // borrowed by `violates`
  scenario::RowViolates violates;
  bool python = false;  // `violates` calls Python: the GIL stays held
};

// Runs `work` with the GIL released unless the constraints call back into Python.
template <class Work>
auto without_gil_unless(const Constraints& constraints, Work work) {
  if (constraints.python) return work();
  const py::gil_scoped_release release;
  return work();
}

void make_constraints(Constraints& out, const std::vector<int>& levels, py::handle constraints,
                      std::uint64_t max_search_steps) {
  if (constraints.is_none()) return;
  if (py::isinstance<py::str>(constraints)) {
    std::string model;
    for (std::size_t i = 0; i < levels.size(); ++i) {
      model += "p" + std::to_string(i + 1) + ":";
      for (int k = 0; k < levels[i]; ++k) model += (k == 0 ? " " : ", ") + std::to_string(k);
      model += "\n";
    }
    const int offset = static_cast<int>(levels.size());
    try {
      out.model.emplace(
          scenario::parse_pict_model(model + constraints.cast<std::string>(), "<constraints>", max_search_steps));
    } catch (const InputError& e) {  // at the line of the constraints as given
      const SourceLocation& at = e.where();
      throw InputError({at.file, at.line > offset ? at.line - offset : 0, at.line > offset ? at.column : 0},
                       e.message());
    }
    out.violates = out.model->row_violates();
    return;
  }
  if (!PyCallable_Check(constraints.ptr()))
    throw py::type_error(
        "emrm.covering_array: constraints must be None, a str of PICT constraints or a function of a row");
  out.python = true;
  out.violates = [function = py::reinterpret_borrow<py::object>(constraints)](std::span<const int> row) {
    return py::bool_(function(py::tuple(py::cast(std::vector<int>(row.begin(), row.end()))))).cast<bool>();
  };
}

void check_strength(int strength) {
  if (strength != 2 && strength != 3)
    throw UsageError("emrm.covering_array: strength must be 2 or 3, got " + std::to_string(strength));
}

scenario::CoveringArrayOptions array_options(int strength, std::uint64_t seed, double effort, std::size_t max_tuples,
                                             std::uint64_t max_search_steps) {
  check_strength(strength);
  scenario::CoveringArrayOptions options;
  options.strength = strength;
  options.seed = seed;
  options.improvement_effort = effort;
  options.max_tuples = max_tuples;
  options.max_search_steps = max_search_steps;
  return options;
}

py::array_t<int> rows_array(const scenario::CoveringArray& ca) {
  py::array_t<int> rows({ca.rows.size(), ca.levels.size()});
  auto out = rows.mutable_unchecked<2>();
  for (std::size_t r = 0; r < ca.rows.size(); ++r)
    for (std::size_t f = 0; f < ca.levels.size(); ++f)
      out(static_cast<py::ssize_t>(r), static_cast<py::ssize_t>(f)) = ca.rows[r][f];
  return rows;
}

py::array_t<int> covering_array(const std::vector<int>& levels, int strength, py::handle constraints,
                                std::uint64_t seed, double effort, std::size_t max_tuples,
                                std::uint64_t max_search_steps) {
  const auto options = array_options(strength, seed, effort, max_tuples, max_search_steps);
  Constraints c;
  make_constraints(c, levels, constraints, max_search_steps);
  return rows_array(
      without_gil_unless(c, [&] { return scenario::generate_covering_array(levels, options, c.violates); }));
}

// The array of a PICT model file: its parameters' names and the values as written, by column.
py::dict covering_array_model(py::handle model_file, int strength, std::uint64_t seed, double effort,
                              std::size_t max_tuples, std::uint64_t max_search_steps) {
  const auto options = array_options(strength, seed, effort, max_tuples, max_search_steps);
  const scenario::PictModel model = scenario::load_pict_model(to_path(model_file), max_search_steps);
  scenario::CoveringArray ca;
  {
    const py::gil_scoped_release release;
    ca = scenario::generate_covering_array(model.levels(), options, model.row_violates());
  }
  py::dict columns;
  for (std::size_t f = 0; f < model.parameters().size(); ++f) {
    py::list values;
    for (const auto& row : ca.rows) values.append(model.parameters()[f].values[static_cast<std::size_t>(row[f])]);
    columns[py::str(model.parameters()[f].name)] = values;
  }
  return columns;
}

py::dict check_covering_array(const std::vector<int>& levels, int strength, const std::vector<std::vector<int>>& rows,
                              py::handle constraints, std::uint64_t max_search_steps) {
  check_strength(strength);
  Constraints c;
  make_constraints(c, levels, constraints, max_search_steps);
  const scenario::ArrayCheck check = without_gil_unless(
      c, [&] { return scenario::check_covering_array(levels, strength, rows, c.violates, max_search_steps); });
  py::dict out;
  out["ok"] = check.ok();
  out["required_tuples"] = check.required_tuples;
  out["covered_tuples"] = check.covered_tuples;
  out["invalid_rows"] = check.invalid_rows;
  out["first_problem"] = check.first_problem;
  return out;
}

// ---- the minimum scenario set ---------------------------------------------------------------

scenario::Odd odd_from(py::handle source, const std::optional<std::filesystem::path>& safety) {
  if (is_path(source)) {
    const std::filesystem::path file = to_path(source);
    if (!std::filesystem::is_regular_file(file)) throw UsageError("emrm.plan: '" + file.string() + "' does not exist");
    return scenario::load_odd(file, safety, workflow::family_levels);
  }
  return parse_mapping(source, [&safety](const std::string& text) {
    return scenario::parse_odd(text, "<odd mapping>", std::filesystem::current_path(), safety, workflow::family_levels);
  });
}

py::dict scenario_columns(const scenario::Odd& odd, const scenario::Plan& plan) {
  // scenarios.csv's columns (scenario::scenarios_csv), the values at full precision.
  py::dict columns;
  const auto text_column = [&](const char* name, auto get) {
    py::list values;
    for (const auto& s : plan.scenarios) values.append(get(s));
    columns[name] = values;
  };
  text_column("id", [](const scenario::Scenario& s) { return s.id; });
  text_column("step", [](const scenario::Scenario& s) { return s.step; });
  for (std::size_t f = 0; f < odd.factors.size(); ++f) {
    py::array_t<double> values(static_cast<py::ssize_t>(plan.scenarios.size()));
    for (std::size_t i = 0; i < plan.scenarios.size(); ++i)
      values.mutable_at(static_cast<py::ssize_t>(i)) = plan.scenarios[i].values[f];
    columns[py::str(odd.factors[f].name)] = values;
  }
  text_column("cell", [](const scenario::Scenario& s) { return scenario::cell_key(s.cell); });
  text_column("malfunctions", [](const scenario::Scenario& s) { return core::join(s.malfunctions, " "); });
  text_column("transitions", [](const scenario::Scenario& s) { return core::join(s.transitions, "; "); });
  py::array_t<double> weights(static_cast<py::ssize_t>(plan.scenarios.size()));
  py::array_t<std::uint64_t> seeds(static_cast<py::ssize_t>(plan.scenarios.size()));
  for (std::size_t i = 0; i < plan.scenarios.size(); ++i) {
    weights.mutable_at(static_cast<py::ssize_t>(i)) = plan.scenarios[i].weight;
    seeds.mutable_at(static_cast<py::ssize_t>(i)) = plan.scenarios[i].seed;
  }
  columns["weight"] = weights;
  columns["seed"] = seeds;
  return columns;
}

// `emrm plan`: the ODD checked against the scene and (when it names one) the safety case, then
// planned, measured against the baselines and written when asked. A safety case with error findings
// refuses the plan unless `allow_findings`: the result then holds the analysis alone.
py::dict plan(py::handle source, py::handle safety_file, py::handle output_dir, bool allow_findings) {
  std::optional<std::filesystem::path> safety;
  if (!safety_file.is_none()) safety = to_path(safety_file);
  const auto start = std::chrono::steady_clock::now();
  const scenario::Odd odd = odd_from(source, safety);
  const sim::SceneConfig scene = workflow::plan_scene(odd);
  workflow::check_odd_against_scene(odd, scene);
  py::dict out;
  std::vector<std::string> warnings;
  if (odd.safety_file) {
    safety::Analysis analysis = workflow::analyze_safety_file(*odd.safety_file);
    const bool refused = analysis.errors() > 0 && !allow_findings;
    if (!refused)
      for (auto& w : workflow::safety_range_warnings(odd, analysis.safety_case)) warnings.push_back(std::move(w));
    out["analysis"] = std::move(analysis);
    if (refused) return out;
  }
  scenario::Plan planned;
  std::vector<scenario::CoverageReport> reports;
  {
    const py::gil_scoped_release release;
    planned = scenario::build_plan(odd);
    reports = scenario::coverage_comparison(odd, planned);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (auto& w : workflow::placement_warnings(odd, planned, scene)) warnings.push_back(std::move(w));
  const std::filesystem::path dir = output_dir.is_none() ? std::filesystem::path(".") : to_path(output_dir);
  if (!output_dir.is_none()) scenario::write_plan(dir, odd, planned, reports);
  const auto [header, rows] = scenario::coverage_table(reports);
  py::dict coverage_columns;
  for (std::size_t c = 0; c < header.size(); ++c) {
    py::list values;
    for (const auto& row : rows) values.append(row[c]);
    coverage_columns[py::str(header[c])] = values;
  }
  out["scenarios"] = scenario_columns(odd, planned);
  out["coverage_table"] = coverage_columns;
  out["coverage"] = to_python(scenario::coverage_json(reports, planned.shortfalls));
  out["plan"] = to_python(scenario::scenarios_json(odd, planned, dir));
  out["targets_met"] = planned.targets_met;
  out["satisfied"] = reports.front().all();
  out["warnings"] = warnings;
  out["text"] = scenario::summary_text(is_path(source) ? to_path(source).string() : "<odd mapping>", odd, planned,
                                       reports, seconds, dir);
  return out;
}

}  // namespace

void bind_scenario(py::module_& m) {
  m.def("covering_array", &covering_array, py::arg("levels"), py::arg("strength") = 2,
        py::arg("constraints") = py::none(), py::kw_only(), py::arg("seed") = 1,
        py::arg("effort") = scenario::CoveringArrayOptions{}.improvement_effort,
        py::arg("max_tuples") = scenario::CoveringArrayOptions{}.max_tuples,
        py::arg("max_search_steps") = scenario::kDefaultMaxSearchSteps,
        "A covering array of strength 2 or 3 over factors with levels[i] values each, as `emrm ca --levels`\n"
        "builds it: a NumPy array of level indices, one row per test. constraints: None; a function of a row\n"
        "(level indices, -1 where not chosen yet) that returns True when the row breaks a constraint (it may\n"
        "say False for a partial row); or PICT constraints over factors named p1, p2, ... whose values are\n"
        "the level indices ('IF [p1] = 0 THEN [p2] <> 2;').");
  m.def("_covering_array_model", &covering_array_model, py::arg("model"), py::arg("strength"), py::arg("seed"),
        py::arg("effort"), py::arg("max_tuples"), py::arg("max_search_steps"));
  m.def("check_covering_array", &check_covering_array, py::arg("levels"), py::arg("strength"), py::arg("rows"),
        py::arg("constraints") = py::none(), py::kw_only(),
        py::arg("max_search_steps") = scenario::kDefaultMaxSearchSteps,
        "Checks rows by brute force, as `emrm ca --check`: every t-tuple a valid row can hold is covered and\n"
        "no row breaks a constraint. Returns {'ok', 'required_tuples', 'covered_tuples', 'invalid_rows',\n"
        "'first_problem'}.");
  m.def("_plan", &plan, py::arg("odd"), py::arg("safety"), py::arg("output_dir"), py::arg("allow_findings"));
}

}  // namespace emrm::python
