#include "emrm/scenario/plan_io.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <optional>
#include <set>

#include "emrm/core/json_archive.hpp"
#include "emrm/core/text.hpp"

namespace emrm::scenario {
namespace {

constexpr const char* kLeadColumns[] = {"id", "step"};
constexpr const char* kTrailColumns[] = {"cell", "malfunctions", "transitions", "weight", "seed"};

std::string number(double v) { return fmt::format("{:.9g}", v); }

std::vector<std::string> split(const std::string& text, std::string_view separator) {
  std::vector<std::string> out;
  if (text.empty()) return out;
  std::size_t start = 0;
  while (true) {
    const auto at = text.find(separator, start);
    out.push_back(text.substr(start, at == std::string::npos ? std::string::npos : at - start));
    if (at == std::string::npos) break;
    start = at + separator.size();
  }
  return out;
}

// "62.5 % (5/8)", as the printed summary shows a coverage.
// The acceptance rule; no strategy named means the registered chooser, resolved when run.
nlohmann::ordered_json acceptance_json(const Odd& odd) {
  nlohmann::ordered_json a = nlohmann::ordered_json::object();
  if (!odd.acceptance_strategy.empty()) a["strategy"] = odd.acceptance_strategy;
  a["outcome"] = core::enum_name(odd.acceptance);
  return a;
}

// Every mode with its region and how many planned tests fall in it, so that `emrm run` keeps the
// modes that got none.
nlohmann::ordered_json malfunctions_json(const Odd& odd, const Plan& plan) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& m : odd.malfunctions) {
    const auto tests = std::count_if(plan.scenarios.begin(), plan.scenarios.end(), [&](const Scenario& s) {
      return std::find(s.malfunctions.begin(), s.malfunctions.end(), m.id) != s.malfunctions.end();
    });
    list.push_back({{"id", m.id},
                    {"region", m.region ? m.region->text() : std::string("true")},
                    {"hazards", m.hazards},
                    {"transitions", m.transitions},
                    {"tests", tests}});
  }
  return list;
}

std::string percent_text(const CoverageCount& c) {
  return fmt::format("{:.1f} % ({}/{})", 100.0 * c.fraction(), c.covered, c.total);
}

std::vector<CoverageReport> reports_from_json(const nlohmann::ordered_json& j, const std::string& file) {
  if (!j.is_object() || !j.contains("plan") || !j.contains("baselines") || !j.at("baselines").is_array())
    throw InputError({file, 0, 0}, "expected a coverage report: an object with \"plan\" and a list \"baselines\"");
  std::vector<CoverageReport> reports;
  reports.push_back(coverage_report_from_json(j.at("plan"), file, "plan"));
  const auto& baselines = j.at("baselines");
  for (std::size_t i = 0; i < baselines.size(); ++i)
    reports.push_back(coverage_report_from_json(baselines[i], file, fmt::format("baselines[{}]", i)));
  return reports;
}

}  // namespace

PlanFactor plan_factor(const OddFactor& f) {
  PlanFactor out{
      .name = f.name, .unit = f.unit, .type = f.type, .levels = {}, .influential = f.influential, .nominal = f.nominal};
  for (int k = 0; k < f.levels(); ++k)
    out.levels.push_back({.level = k, .label = f.level_label(k), .prior = f.prior[static_cast<std::size_t>(k)]});
  return out;
}

std::string scenarios_csv(const Odd& odd, const Plan& plan) {
  core::Row header(std::begin(kLeadColumns), std::end(kLeadColumns));
  for (const auto& f : odd.factors) header.push_back(f.name);
  header.insert(header.end(), std::begin(kTrailColumns), std::end(kTrailColumns));
  std::vector<core::Row> rows;
  for (const auto& s : plan.scenarios) {
    core::Row row{s.id, s.step};
    for (double v : s.values) row.push_back(number(v));
    row.push_back(cell_key(s.cell));
    row.push_back(core::join(s.malfunctions, " "));
    row.push_back(core::join(s.transitions, "; "));
    row.push_back(number(s.weight));
    row.push_back(std::to_string(s.seed));
    rows.push_back(std::move(row));
  }
  return core::csv_table(header, rows);
}

nlohmann::ordered_json scenarios_json(const Odd& odd, const Plan& plan, const std::filesystem::path& folder) {
  const auto relative = [&folder](const std::filesystem::path& p) {
    std::error_code ec;
    const auto r = std::filesystem::relative(std::filesystem::absolute(p), std::filesystem::absolute(folder), ec);
    return (ec || r.empty() ? p : r).generic_string();
  };
  nlohmann::ordered_json j;
  j["odd"] = {{"file", relative(odd.file)}, {"name", odd.name}};
  if (odd.safety_file) j["odd"]["safety"] = relative(*odd.safety_file);
  if (odd.scene_file) j["odd"]["scene"] = relative(*odd.scene_file);
  j["settings"] = {{"seed", odd.seed},
                   {"strength", odd.strength},
                   {"n_c", odd.n_c},
                   {"n_m", odd.n_m},
                   {"epsilon", odd.epsilon},
                   {"delta", odd.delta},
                   {"budget", odd.budget},
                   {"strategies", odd.strategies},
                   {"acceptance", acceptance_json(odd)},
                   {"relevance", odd.relevance ? odd.relevance->text() : std::string("true")},
                   {"tracked", odd.tracked ? odd.tracked->text() : std::string("every relevant cell")}};
  nlohmann::ordered_json factors = nlohmann::ordered_json::array();
  for (const auto& f : odd.factors) factors.push_back(core::write_json(plan_factor(f)));
  j["factors"] = factors;
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  for (const auto& s : plan.steps) steps.push_back({{"step", s.name}, {"added", s.added}, {"what", s.note}});
  j["steps"] = steps;
  j["stop"] = {{"targets_met", plan.targets_met},
               {"reason", plan.stop_reason},
               {"relevant_cells", plan.relevant_cells},
               {"tracked_cells", plan.tracked_cells},
               {"tests_per_tracked_cell", plan.tests_per_tracked_cell},
               {"infeasible", plan.infeasible},
               {"shortfalls", shortfalls_json(plan.shortfalls)}};
  j["malfunctions"] = malfunctions_json(odd, plan);
  std::map<std::vector<int>, std::size_t> planned;
  for (const auto& s : plan.scenarios) ++planned[s.cell];
  nlohmann::ordered_json cells = nlohmann::ordered_json::array();
  for (const auto& c : plan.cells) {
    nlohmann::ordered_json levels;
    for (std::size_t i = 0; i < odd.factors.size(); ++i)
      levels[odd.factors[i].name] = odd.factors[i].level_label(c.levels[i]);
    cells.push_back({{"cell", cell_key(c.levels)},
                     {"levels", levels},
                     {"prior", c.prior},
                     {"tracked", c.tracked},
                     {"scenarios", planned[c.levels]}});
  }
  j["cells"] = cells;
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& s : plan.scenarios) {
    nlohmann::ordered_json values, cell;
    for (std::size_t i = 0; i < odd.factors.size(); ++i) {
      values[odd.factors[i].name] = s.values[i];
      cell[odd.factors[i].name] = odd.factors[i].level_label(s.cell[i]);
    }
    list.push_back({{"id", s.id},
                    {"step", s.step},
                    {"values", values},
                    {"cell", cell_key(s.cell)},
                    {"cell_levels", cell},
                    {"malfunctions", s.malfunctions},
                    {"transitions", s.transitions},
                    {"weight", s.weight},
                    {"seed", s.seed}});
  }
  j["scenarios"] = list;
  return j;
}

std::vector<CoverageReport> coverage_comparison(const Odd& odd, const Plan& plan) {
  std::vector<std::vector<double>> points;
  for (const auto& s : plan.scenarios) points.push_back(s.values);
  std::vector<CoverageReport> reports;
  reports.push_back(measure_coverage(odd, points, "emrm plan"));
  reports.push_back(measure_coverage(odd, hara_only_baseline(odd), "HARA only"));
  reports.push_back(measure_coverage(odd, stpa_only_baseline(odd), "STPA only"));
  if (!odd.manual_grid.empty()) reports.push_back(measure_coverage(odd, manual_baseline(odd), "manual grid"));
  return reports;
}

nlohmann::ordered_json shortfalls_json(const std::vector<Shortfall>& shortfalls) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& s : shortfalls)
    list.push_back({{"kind", core::enum_name(s.kind)},
                    {"subject", s.subject},
                    {"found", s.found},
                    {"needed", s.needed},
                    {"message", s.message}});
  return list;
}

nlohmann::ordered_json coverage_json(const std::vector<CoverageReport>& reports,
                                     const std::vector<Shortfall>& shortfalls) {
  nlohmann::ordered_json j;
  j["plan"] = to_json(reports.front());
  j["baselines"] = nlohmann::ordered_json::array();
  for (std::size_t i = 1; i < reports.size(); ++i) j["baselines"].push_back(to_json(reports[i]));
  j["shortfalls"] = shortfalls_json(shortfalls);
  return j;
}

std::vector<CoverageReport> parse_coverage_json(const std::string& text, const std::string& file_name) {
  const auto j = nlohmann::ordered_json::parse(text, nullptr, false);
  if (j.is_discarded()) throw InputError({file_name, 1, 1}, "not valid JSON");
  return reports_from_json(j, file_name);
}

std::vector<CoverageReport> read_coverage_json(const std::filesystem::path& path) {
  return parse_coverage_json(core::read_input_file(path), path.string());
}

std::pair<core::Row, std::vector<core::Row>> coverage_table(const std::vector<CoverageReport>& reports) {
  core::Row header{"metric"};
  for (const auto& r : reports) header.push_back(r.name);
  std::vector<core::Row> rows;
  const auto percent_row = [&](const std::string& label, auto member) {
    core::Row row{label};
    for (const auto& r : reports) {
      const CoverageCount& c = r.*member;
      row.push_back(fmt::format("{:.1f} ({}/{})", 100.0 * c.fraction(), c.covered, c.total));
    }
    rows.push_back(std::move(row));
  };
  const auto flag_row = [&](const std::string& label, auto member) {
    core::Row row{label};
    for (const auto& r : reports) row.push_back(r.*member ? "holds" : "fails");
    rows.push_back(std::move(row));
  };
  core::Row size{"scenarios"};
  for (const auto& r : reports) size.push_back(std::to_string(r.scenarios));
  rows.push_back(std::move(size));
  percent_row("hazard coverage %", &CoverageReport::hazards);
  percent_row("UCA coverage %", &CoverageReport::malfunctions);
  percent_row("FSM transition coverage %", &CoverageReport::transitions);
  percent_row("cell coverage %", &CoverageReport::cells);
  percent_row("t-wise coverage %", &CoverageReport::twise);
  percent_row("boundary coverage %", &CoverageReport::boundaries);
  flag_row("C1 cells", &CoverageReport::c1);
  flag_row("C2 boundaries", &CoverageReport::c2);
  flag_row("C3 t-wise", &CoverageReport::c3);
  flag_row("C4 malfunctions", &CoverageReport::c4);
  return {header, rows};
}

void write_plan(const std::filesystem::path& dir, const Odd& odd, const Plan& plan,
                const std::vector<CoverageReport>& reports) {
  // All five or none: `emrm run` reads scenarios.csv with the scenarios.json beside it.
  const auto [header, rows] = coverage_table(reports);
  const PlanDir files(dir);
  core::write_files({{files.scenarios_csv(), scenarios_csv(odd, plan)},
                     {files.scenarios_json(), scenarios_json(odd, plan, dir).dump(2) + "\n"},
                     {files.coverage_json(), coverage_json(reports, plan.shortfalls).dump(2) + "\n"},
                     {files.coverage_csv(), core::csv_table(header, rows)},
                     {files.coverage_md(), "# Coverage: " + odd.name + "\n\n" + core::markdown_table(header, rows)}});
}

std::string summary_text(const std::string& odd_file, const Odd& odd, const Plan& plan,
                         const std::vector<CoverageReport>& reports, double seconds, const std::filesystem::path& dir) {
  std::string out;
  out += fmt::format("plan      {}: {} factors, {:.0f} cells, {} relevant, {} tracked, {} malfunction modes\n",
                     odd_file, odd.factors.size(), odd.cell_count(), plan.relevant_cells, plan.tracked_cells,
                     odd.malfunctions.size());
  for (const auto& step : plan.steps) out += fmt::format("  {:<15} +{:<4} {}\n", step.name, step.added, step.note);
  out += fmt::format("  {} scenarios in {:.2f} s; {}\n", plan.scenarios.size(), seconds, plan.stop_reason);
  for (const auto& note : plan.infeasible) out += fmt::format("  no admissible point (exempt from C2): {}\n", note);
  for (const auto& s : plan.shortfalls) out += fmt::format("  shortfall: {}\n", s.message);
  const auto& ours = reports.front();
  out += fmt::format("  coverage: hazards {}, UCAs {}, transitions {}, cells {}, {}-wise {}, boundaries {}\n",
                     percent_text(ours.hazards), percent_text(ours.malfunctions), percent_text(ours.transitions),
                     percent_text(ours.cells), odd.strength, percent_text(ours.twise), percent_text(ours.boundaries));
  out += fmt::format("  independent check: C1 {}, C2 {}, C3 {}, C4 {}\n", ours.c1 ? "holds" : "FAILS",
                     ours.c2 ? "holds" : "FAILS", ours.c3 ? "holds" : "FAILS", ours.c4 ? "holds" : "FAILS");
  for (std::size_t i = 1; i < reports.size(); ++i)
    out += fmt::format("  baseline {:<12} {:>3} scenarios: hazards {}, UCAs {}, cells {}\n", reports[i].name,
                       reports[i].scenarios, percent_text(reports[i].hazards), percent_text(reports[i].malfunctions),
                       percent_text(reports[i].cells));
  out += fmt::format("  -> {}\n", PlanDir(dir).scenarios_csv().string());
  return out;
}

ScenarioFile read_scenarios_csv(const std::filesystem::path& path) {
  const std::string text = core::read_input_file(path);
  const std::string name = path.string();
  const auto records = core::parse_csv(text, name);
  if (records.empty()) throw InputError({name, 1, 1}, "empty file; expected a header line of a scenarios.csv");
  const core::CsvRecord& header = records.front();
  const auto& h = header.fields;
  const std::size_t lead = std::size(kLeadColumns);
  const std::size_t trail = std::size(kTrailColumns);
  const auto expected = fmt::format("expected the header id, step, the factor columns, then {}",
                                    core::join({std::begin(kTrailColumns), std::end(kTrailColumns)}, ", "));
  if (h.size() < lead + trail + 1) throw InputError({name, 1, 1}, fmt::format("{} columns; {}", h.size(), expected));
  for (std::size_t i = 0; i < lead; ++i)
    if (h[i] != kLeadColumns[i])
      throw InputError({name, header.lines[i], header.columns[i]},
                       fmt::format("column {} is '{}', not '{}'; {}", i + 1, h[i], kLeadColumns[i], expected));
  for (std::size_t i = 0; i < trail; ++i) {
    const std::size_t at = h.size() - trail + i;
    if (h[at] != kTrailColumns[i])
      throw InputError({name, header.lines[at], header.columns[at]},
                       fmt::format("column {} is '{}', not '{}'; {}", at + 1, h[at], kTrailColumns[i], expected));
  }
  ScenarioFile file;
  file.file = name;
  file.factors.assign(h.begin() + static_cast<std::ptrdiff_t>(lead), h.end() - static_cast<std::ptrdiff_t>(trail));
  std::set<std::string> ids;
  for (std::size_t r = 1; r < records.size(); ++r) {
    const core::CsvRecord& rec = records[r];
    const auto at = [&](std::size_t i) { return SourceLocation{name, rec.lines[i], rec.columns[i]}; };
    core::check_row_length(rec, h.size(), name);
    ScenarioRow row;
    row.where = at(0);
    row.id = rec.fields[0];
    if (row.id.empty()) throw InputError(at(0), "empty scenario id");
    if (!ids.insert(row.id).second) throw InputError(at(0), fmt::format("duplicate scenario id '{}'", row.id));
    row.step = rec.fields[1];
    for (std::size_t i = lead; i < h.size() - trail; ++i) {
      const std::string& f = rec.fields[i];
      const std::optional<double> v = core::parse_finite_number(f);
      if (!v) throw InputError(at(i), fmt::format("{}: expected a finite number, got '{}'", h[i], f));
      row.values.push_back(*v);
    }
    const std::size_t t = h.size() - trail;
    row.cell = rec.fields[t];
    row.malfunctions = split(rec.fields[t + 1], " ");
    row.transitions = split(rec.fields[t + 2], "; ");
    {
      const std::string& f = rec.fields[t + 3];
      const std::optional<double> weight = core::parse_finite_number(f);
      if (!weight || *weight < 0.0)
        throw InputError(at(t + 3), fmt::format("weight: expected a finite number >= 0, got '{}'", f));
      row.weight = *weight;
    }
    {
      const std::string& f = rec.fields[t + 4];
      const auto seed = core::parse_whole_number<std::uint64_t>(f);
      if (!seed) throw InputError(at(t + 4), fmt::format("seed: expected an unsigned 64-bit integer, got '{}'", f));
      row.seed = *seed;
    }
    file.rows.push_back(std::move(row));
  }
  return file;
}

}  // namespace emrm::scenario
