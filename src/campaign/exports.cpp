#include "emrm/campaign/exports.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "emrm/campaign/store.hpp"
#include "emrm/core/text.hpp"

namespace emrm::campaign {
namespace {

std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.6g}", v);
}

}  // namespace

std::vector<GridCount> write_exports(const std::filesystem::path& results_sqlite, const std::filesystem::path& dir) {
  const ResultStore store = ResultStore::open_for_reading(results_sqlite);
  const sim::FactorTable table = scenario_factors(store.meta());
  const auto keys = table.keys();
  // Streamed into temporaries beside the targets (core::OutputFile), renamed only once all three
  // are complete: a reader never sees half a file, and a failure (a corrupt row, a full disk)
  // leaves the previous exports and no temporary.
  core::OutputFile regions_file(dir / kRegionsCsv);
  core::OutputFile cells_file(dir / kCellsCsv);
  core::OutputFile json_file(dir / kCellsJson);
  std::ostream& regions = regions_file.stream();
  std::ostream& cells = cells_file.stream();
  std::ostream& json = json_file.stream();
  core::Row factor_header{"grid"};
  factor_header.insert(factor_header.end(), keys.begin(), keys.end());
  const auto header = [&](std::initializer_list<std::string> rest) {
    core::Row row = factor_header;
    row.insert(row.end(), rest);
    return core::csv_line(row);
  };
  regions << header(
      {"feasible", "region", "evidence", "mitigation_evidence", "p_mais3_reduction", "p_fatal_reduction", "method"});
  cells << header({"strategy", "avoided", "impact_speed_kph", "delta_v_kph", "loss_level", "delta_loss", "min_ttc_s",
                   "road_departure", "departure_speed_kph", "evidence"});
  json << "[";
  bool first = true;
  std::vector<GridCount> counts;
  store.for_each_cell([&](const CellRecord& r) {
    auto count = std::find_if(counts.begin(), counts.end(), [&](const GridCount& c) { return c.grid == r.grid; });
    if (count == counts.end()) count = counts.insert(counts.end(), GridCount{r.grid, 0, 0});
    ++count->cells;
    count->feasible += r.feasible;
    core::Row factors{r.grid};
    for (const double v : r.factors) factors.push_back(number(v));
    core::Row region = factors;
    region.push_back(r.feasible ? "1" : "0");
    region.push_back(core::enum_text(r.region));
    region.push_back(core::enum_text(r.evidence));
    region.push_back(core::enum_text(r.mitigation_evidence));
    region.push_back(r.simulated() ? number(r.p_mais3_reduction) : "");
    region.push_back(r.simulated() ? number(r.p_fatal_reduction) : "");
    region.push_back(r.feasible ? core::enum_text(r.method) : "");
    regions << core::csv_line(region);
    nlohmann::ordered_json j{{"grid", r.grid}, {"index", r.index}};
    for (std::size_t f = 0; f < keys.size() && f < r.factors.size(); ++f) j[keys[f]] = r.factors[f];
    j["seed"] = r.seed;
    j["feasible"] = r.feasible;
    j["region"] = core::enum_text(r.region);
    if (r.feasible && r.method == CellMethod::kInferred) {
      j["method"] = core::enum_text(r.method);
      j["inferred_from"] = r.inferred_from;
    } else if (r.feasible) {
      j["method"] = core::enum_text(r.method);
      j["evidence"] = core::enum_text(r.evidence);
      if (r.mitigation_evidence != sim::MitigationEvidence::kNone)
        j["mitigation_evidence"] = core::enum_text(r.mitigation_evidence);
      j["strengthened"] = r.strengthened;
      if (!r.certificate.empty()) {
        try {
          j["certificate"] = nlohmann::ordered_json::parse(r.certificate);
        } catch (const nlohmann::json::parse_error& e) {  // a store damaged or edited by hand
          throw InputError(
              SourceLocation{results_sqlite.string()},
              fmt::format("cell {}#{}: the stored certificate is not JSON: {}", r.grid, r.index, e.what()));
        }
      }
      j["harm_reduction"] = {{"p_mais3", r.p_mais3_reduction}, {"p_fatal", r.p_fatal_reduction}};
      j["unmitigated"] = {{"impact_speed_kph", r.unmitigated_impact_speed_kph},
                          {"delta_v_kph", r.unmitigated_delta_v_kph},
                          {"p_mais3", r.unmitigated_p_mais3},
                          {"p_fatal", r.unmitigated_p_fatal},
                          {"loss_level", r.unmitigated_loss_level}};
      auto& outcomes = j["outcomes"] = nlohmann::ordered_json::array();
      for (const auto& o : r.outcomes) {
        core::Row row = factors;
        row.insert(row.end(),
                   {o.strategy, o.avoided ? "1" : "0", number(o.impact_speed_kph), number(o.delta_v_kph),
                    std::to_string(o.loss_level), std::to_string(o.delta_loss), number(o.min_ttc_s),
                    o.road_departure ? "1" : "0", number(o.departure_speed_kph()), core::enum_text(o.evidence)});
        cells << core::csv_line(row);
        outcomes.push_back({{"strategy", o.strategy},
                            {"avoided", o.avoided},
                            {"contact", o.contact},
                            {"road_departure", o.road_departure},
                            {"departure_speed_kph", o.departure_speed_kph()},
                            {"evidence", core::enum_text(o.evidence)},
                            {"impact_speed_kph", o.impact_speed_kph},
                            {"delta_v_kph", o.delta_v_kph},
                            {"p_mais3", o.p_mais3},
                            {"p_fatal", o.p_fatal},
                            {"loss_level", o.loss_level},
                            {"delta_loss", o.delta_loss},
                            {"min_ttc_s", std::isfinite(o.min_ttc_s) ? nlohmann::ordered_json(o.min_ttc_s)
                                                                     : nlohmann::ordered_json(nullptr)},
                            {"fsm_trace", o.fsm_trace},
                            {"loss_evaluation_trace", o.loss_evaluation_trace},
                            {"chosen_strategy", o.chosen_strategy},
                            {"adopted_from", o.adopted_from}});
      }
    }
    json << (first ? "\n" : ",\n") << j.dump();
    first = false;
  });
  json << "\n]\n";
  for (auto* file : {&regions_file, &cells_file, &json_file}) file->close();
  for (auto* file : {&regions_file, &cells_file, &json_file}) file->commit();
  return counts;
}

}  // namespace emrm::campaign
