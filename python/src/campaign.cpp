// Sweeps and results stores (docs/campaign.md): campaign::sweep with the GIL released and Ctrl-C
// stopping it as it stops `emrm sweep`, and a store's cells, outcomes and KPIs as columns for pandas.

#include "emrm/campaign/campaign.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdint>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>
#include <type_traits>

#include "bindings.hpp"
#include "emrm/campaign/adaptive.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/campaign/sweep.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/core/text.hpp"
#include "emrm/results/aggregate.hpp"

namespace emrm::python {
namespace {

campaign::Campaign campaign_from(py::handle source, bool force) {
  if (is_path(source)) return campaign::load_campaign(to_path(source), force);
  return parse_mapping(source, [force](const std::string& text) {
    return campaign::parse_campaign(text, "<campaign mapping>", std::filesystem::current_path(), force);
  });
}

// Runs the sweep on a thread of its own while this one, the interpreter's, looks for signals ten
// times a second with the GIL held only for that look. Python's own SIGINT handler stays in place:
// when it reports Ctrl-C the sweep is asked to stop (core::request_interrupt), stores the cells in
// flight and throws core::Interrupted, which reaches Python as emrm.Interrupted (a
// KeyboardInterrupt). A second Ctrl-C while it stops changes nothing; the interpreter lives on.
campaign::SweepSummary sweep_interruptibly(const campaign::Campaign& campaign, const campaign::SweepOptions& options) {
  struct Shared {
    std::mutex mutex;
    std::condition_variable finished;
    bool done = false;
    campaign::SweepSummary summary;
    std::exception_ptr error;
  } shared;
  std::optional<py::error_already_set> signalled;  // what the interpreter's handler raised
  core::clear_interrupt();
  {
    const py::gil_scoped_release release;
    std::thread worker([&] {
      try {
        shared.summary = campaign::sweep(campaign, options);
      } catch (...) {
        shared.error = std::current_exception();
      }
      const std::lock_guard lock(shared.mutex);
      shared.done = true;
      shared.finished.notify_all();
    });
    std::unique_lock lock(shared.mutex);
    while (!shared.finished.wait_for(lock, std::chrono::milliseconds(100), [&] { return shared.done; })) {
      lock.unlock();
      {
        const py::gil_scoped_acquire acquire;
        if (PyErr_CheckSignals() != 0) {
          if (signalled)
            PyErr_Clear();  // stopping already
          else
            signalled.emplace();  // takes the error out of the interpreter
          core::request_interrupt(SIGINT);
        }
      }
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (signalled && !signalled->matches(PyExc_KeyboardInterrupt)) throw *signalled;  // a handler of the user's
  if (shared.error) std::rethrow_exception(shared.error);
  if (signalled) throw *signalled;  // the sweep had just finished when Ctrl-C came
  return shared.summary;
}

// The adaptive search's settings from _sweep's keywords (their defaults adaptive::Options{}'s, in
// bind_campaign), checked before the sweep opens its store.
campaign::adaptive::Options search_options(std::optional<std::size_t> verify_sample, std::size_t initial_levels,
                                           std::size_t stride, const std::string& brackets, std::uint32_t spread) {
  campaign::adaptive::Options search;
  search.verify_sample = verify_sample;
  search.initial_levels = initial_levels;
  search.stride = stride;
  const auto named = campaign::adaptive::brackets_named(brackets);
  if (!named)
    throw UsageError(fmt::format("emrm.sweep: brackets: expected one of {}, got '{}'",
                                 fmt::join(campaign::adaptive::kBracketsNames, ", "), brackets));
  search.brackets = *named;
  search.spread = spread;
  campaign::adaptive::check(search);  // std::invalid_argument: ValueError
  return search;
}

py::dict sweep(py::handle source, py::handle output_dir, int threads, bool progress,
               const std::optional<std::string>& profile, bool force, const std::string& shard, bool adaptive,
               py::handle progress_log, std::optional<std::size_t> verify_sample, std::size_t initial_levels,
               std::size_t stride, const std::string& brackets, std::uint32_t spread) {
  campaign::SweepOptions options;
  campaign::parse_shard(shard, options.shard_index, options.shard_count);
  options.output_dir = to_path(output_dir);
  options.threads = threads;
  options.progress = progress;
  options.adaptive = adaptive;
  options.search = search_options(verify_sample, initial_levels, stride, brackets, spread);
  if (!progress_log.is_none()) options.progress_log = to_path(progress_log);
  campaign::Campaign c = campaign_from(source, force);
  if (profile) campaign::apply_profile(c, *profile);
  const campaign::SweepSummary s = sweep_interruptibly(c, options);
  py::list adaptive_summaries;
  for (const auto& a : s.adaptive) adaptive_summaries.append(to_python(nlohmann::ordered_json::parse(a.json)));
  py::dict summary;
  summary["cells_total"] = s.cells_total;
  summary["cells_done_before"] = s.cells_done_before;
  summary["cells_simulated"] = s.cells_simulated;
  summary["seconds"] = s.seconds;
  summary["adaptive"] = adaptive_summaries;
  return summary;
}

// Columns of a table, one row per element of `rows`: numbers and flags as NumPy arrays, text as lists.
template <class Row>
class Columns {
 public:
  explicit Columns(const std::vector<Row>& rows) : rows_(rows) {}

  template <class Get>
  void add(const std::string& name, Get get) {
    using T = std::decay_t<decltype(get(std::declval<const Row&>()))>;
    if constexpr (std::is_arithmetic_v<T>) {
      py::array_t<T> values(static_cast<py::ssize_t>(rows_.size()));
      T* data = values.mutable_data();
      for (std::size_t i = 0; i < rows_.size(); ++i) data[i] = get(rows_[i]);
      columns_[py::str(name)] = values;
    } else {
      py::list values(rows_.size());
      for (std::size_t i = 0; i < rows_.size(); ++i) values[i] = py::str(get(rows_[i]));
      columns_[py::str(name)] = values;
    }
  }
  // Every field of Record's field list (docs/architecture.md, "The record field list") that is not a
  // column yet, under its own name and in the list's order (enums by name, lists as words): a field
  // added to a record is a column of the frames without another edit. `of(row)` is the row's record.
  // `renamed`: fields a column holds under another name. One visit of each row's record fills them all.
  template <class Record, class Of>
  void add_remaining_fields(Of of, std::initializer_list<std::string_view> renamed = {}) {
    const auto n = static_cast<py::ssize_t>(rows_.size());
    // By the field's position in the list: whether it is added, and its NumPy array's data or its list.
    std::vector<bool> added;
    std::vector<void*> numbers;
    std::vector<py::list> texts;
    const Record probe;
    Record::visit_fields(probe, [&](const char* name, const auto& field, auto...) {
      using T = std::remove_cvref_t<decltype(field)>;
      bool add = false;
      void* data = nullptr;
      py::list text;
      if constexpr (!std::is_same_v<T, sim::CellInput>) {  // the factors: a column each, by key
        add = !columns_.contains(name) && std::find(renamed.begin(), renamed.end(), name) == renamed.end();
        if constexpr (std::is_arithmetic_v<T>) {
          if (add) {
            py::array_t<T> values(n);
            data = values.mutable_data();
            columns_[py::str(name)] = values;
          }
        } else if (add) {
          text = py::list(n);
          columns_[py::str(name)] = text;
        }
      }
      added.push_back(add);
      numbers.push_back(data);
      texts.push_back(std::move(text));
    });
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      std::size_t at = 0;
      Record::visit_fields(of(rows_[i]), [&](const char*, const auto& field, auto...) {
        using T = std::remove_cvref_t<decltype(field)>;
        if (!added[at++]) return;
        if constexpr (std::is_arithmetic_v<T>)
          static_cast<T*>(numbers[at - 1])[i] = field;
        else if constexpr (!std::is_same_v<T, sim::CellInput>)
          texts[at - 1][i] = py::str(text_of(field));
      });
    }
  }
  [[nodiscard]] py::dict dict() const { return columns_; }

 private:
  // A field that is not a number, as text: enums by name, lists as words.
  template <class T>
  static std::string text_of(const T& field) {
    if constexpr (std::is_same_v<T, std::string>)
      return field;
    else if constexpr (core::NamedEnum<T>)
      return std::string(core::enum_text(field));
    else if constexpr (std::is_same_v<T, std::vector<std::string>>)
      return core::join(field, " ");
    else
      return fmt::format("{}", fmt::join(field, " "));
  }

  const std::vector<Row>& rows_;
  py::dict columns_;
};

// grid, index and a column per factor of the store's scene, named by its key.
template <class Row, class Cell>
void add_cell_factors(Columns<Row>& columns, const sim::FactorTable& factors, Cell cell) {
  columns.add("grid", [cell](const Row& r) -> const std::string& { return cell(r).grid; });
  columns.add("index", [cell](const Row& r) { return cell(r).index; });
  for (std::size_t f = 0; f < factors.size(); ++f)
    columns.add(factors[f].key,
                [cell, f](const Row& r) { return f < cell(r).factors.size() ? cell(r).factors[f] : 0.0; });
}

// regions.csv's columns (at full precision; the reductions NaN where it leaves them blank), then
// the rest of the cell's fields.
py::dict region_columns(const std::vector<campaign::CellRecord>& records, const sim::FactorTable& factors) {
  using campaign::CellRecord;
  constexpr double kBlank = std::numeric_limits<double>::quiet_NaN();
  Columns<CellRecord> c(records);
  add_cell_factors(c, factors, [](const CellRecord& r) -> const CellRecord& { return r; });
  c.add("feasible", [](const CellRecord& r) { return r.feasible; });
  c.add("region", [](const CellRecord& r) { return core::enum_text(r.region); });
  c.add("evidence", [](const CellRecord& r) { return core::enum_text(r.evidence); });
  c.add("mitigation_evidence", [](const CellRecord& r) { return core::enum_text(r.mitigation_evidence); });
  c.add("p_mais3_reduction", [](const CellRecord& r) { return r.simulated() ? r.p_mais3_reduction : kBlank; });
  c.add("p_fatal_reduction", [](const CellRecord& r) { return r.simulated() ? r.p_fatal_reduction : kBlank; });
  c.add("method", [](const CellRecord& r) { return r.feasible ? core::enum_text(r.method) : std::string(); });
  c.add_remaining_fields<CellRecord>([](const CellRecord& r) -> const CellRecord& { return r; }, {"cell_index"});
  return c.dict();
}

struct OutcomeRow {
  const campaign::CellRecord* cell;
  const campaign::OutcomeRecord* outcome;
};

// cells.csv's columns, then the rest of each outcome's fields and the cell's seed.
py::dict outcome_columns(const std::vector<campaign::CellRecord>& records, const sim::FactorTable& factors) {
  std::vector<OutcomeRow> rows;
  for (const auto& r : records)
    for (const auto& o : r.outcomes) rows.push_back({&r, &o});
  Columns<OutcomeRow> c(rows);
  add_cell_factors(c, factors, [](const OutcomeRow& r) -> const campaign::CellRecord& { return *r.cell; });
  c.add("strategy", [](const OutcomeRow& r) { return r.outcome->strategy; });
  c.add("avoided", [](const OutcomeRow& r) { return r.outcome->avoided; });
  c.add("impact_speed_kph", [](const OutcomeRow& r) { return r.outcome->impact_speed_kph; });
  c.add("delta_v_kph", [](const OutcomeRow& r) { return r.outcome->delta_v_kph; });
  c.add("loss_level", [](const OutcomeRow& r) { return r.outcome->loss_level; });
  c.add("delta_loss", [](const OutcomeRow& r) { return r.outcome->delta_loss; });
  c.add("min_ttc_s", [](const OutcomeRow& r) { return r.outcome->min_ttc_s; });
  c.add("road_departure", [](const OutcomeRow& r) { return r.outcome->road_departure; });
  c.add("departure_speed_kph", [](const OutcomeRow& r) { return r.outcome->departure_speed_kph(); });
  c.add("evidence", [](const OutcomeRow& r) { return core::enum_text(r.outcome->evidence); });
  c.add_remaining_fields<campaign::OutcomeRecord>(
      [](const OutcomeRow& r) -> const campaign::OutcomeRecord& { return *r.outcome; });
  c.add("seed", [](const OutcomeRow& r) { return r.cell->seed; });
  return c.dict();
}

// kpis.csv's columns (results::grid_kpis of every grid), at full precision.
py::dict kpi_columns(const std::vector<campaign::CellRecord>& records, const results::LevelCuts& cuts) {
  using results::StrategyKpis;
  std::vector<StrategyKpis> kpis;
  for (const auto& grid : results::grid_names(records))
    for (auto& k : results::grid_kpis(records, grid, cuts)) kpis.push_back(std::move(k));
  Columns<StrategyKpis> c(kpis);
  c.add("grid", [](const StrategyKpis& k) { return k.grid; });
  c.add("strategy", [](const StrategyKpis& k) { return k.strategy; });
  c.add("factor", [](const StrategyKpis& k) { return std::string(results::factor_name(k.factor)); });
  c.add("level", [](const StrategyKpis& k) { return k.level; });
  c.add("range", [&cuts](const StrategyKpis& k) { return results::level_range(k.factor, k.level, cuts); });
  c.add("cells", [](const StrategyKpis& k) { return k.cells; });
  c.add("avoided", [](const StrategyKpis& k) { return k.avoided; });
  c.add("collisions", [](const StrategyKpis& k) { return k.collisions; });
  c.add("mitigated", [](const StrategyKpis& k) { return k.mitigated; });
  c.add("collision_avoidance_rate_pct", [](const StrategyKpis& k) { return k.collision_avoidance_rate_pct; });
  c.add("mean_impact_speed_kph", [](const StrategyKpis& k) { return k.mean_impact_speed_kph; });
  c.add("mean_impact_speed_collisions_kph", [](const StrategyKpis& k) { return k.mean_impact_speed_collisions_kph; });
  c.add("mean_min_ttc_s", [](const StrategyKpis& k) { return k.mean_min_ttc_s; });
  c.add("finite_min_ttc_cells", [](const StrategyKpis& k) { return k.finite_min_ttc; });
  c.add("mitigability_success_pct", [](const StrategyKpis& k) { return k.mitigability_success_pct; });
  c.add("mean_delta_loss", [](const StrategyKpis& k) { return k.mean_delta_loss; });
  c.add("differs_from_oracle_pct", [](const StrategyKpis& k) { return k.differs_from_oracle_pct; });
  return c.dict();
}

py::dict read_results(py::handle dir) {
  const auto store = campaign::results_store_in(to_path(dir), "emrm.load_results");
  const campaign::CampaignMeta meta = campaign::read_meta(store);
  std::vector<campaign::CellRecord> records;
  std::vector<std::pair<std::string, std::string>> adaptive;
  {
    const py::gil_scoped_release release;
    records = campaign::read_results(store);
    adaptive = campaign::ResultStore::open_for_reading(store).adaptive_summaries();
  }
  // The KPI tables cut the passage at the car's width, as `emrm reproduce` does.
  const sim::SceneConfig scene = sim::parse_stored_scene_config(meta.scene_yaml, store.string());
  const results::LevelCuts cuts = results::level_cuts(scene);
  const sim::FactorTable factors = sim::scenario_factors(scene);
  py::dict meta_dict;
  meta_dict["config_hash"] = meta.config_hash;
  meta_dict["emrm_version"] = meta.emrm_version;
  meta_dict["seed"] = meta.seed;
  meta_dict["strategies"] = meta.strategies;
  meta_dict["grids"] = meta.grids;
  meta_dict["shard_index"] = meta.shard_index;
  meta_dict["shard_count"] = meta.shard_count;
  meta_dict["campaign_yaml"] = meta.campaign_yaml;
  meta_dict["scene_yaml"] = meta.scene_yaml;
  py::dict adaptive_dict;
  for (const auto& [grid, json] : adaptive)
    adaptive_dict[py::str(grid)] = to_python(nlohmann::ordered_json::parse(json));
  py::dict out;
  out["regions"] = region_columns(records, factors);
  out["cells"] = outcome_columns(records, factors);
  out["kpis"] = kpi_columns(records, cuts);
  out["meta"] = meta_dict;
  out["adaptive"] = adaptive_dict;
  return out;
}

}  // namespace

void bind_campaign(py::module_& m) {
  const campaign::adaptive::Options search;  // the defaults of the search's keywords
  m.def("_sweep", &sweep, py::arg("campaign"), py::arg("output_dir"), py::arg("threads"), py::arg("progress"),
        py::arg("profile"), py::arg("force"), py::arg("shard"), py::arg("adaptive"), py::arg("progress_log"),
        py::kw_only(), py::arg("verify_sample") = search.verify_sample,
        py::arg("initial_levels") = search.initial_levels, py::arg("stride") = search.stride,
        py::arg("brackets") = std::string(campaign::adaptive::brackets_name(search.brackets)),
        py::arg("spread") = search.spread,
        "campaign::sweep into output_dir (emrm.sweep wraps it); returns the summary. The adaptive search's "
        "keywords default to emrm sweep's (adaptive::Options).");
  m.def("_read_results", &read_results, py::arg("dir"),
        "A results folder's cells, outcomes, KPIs and metadata as columns (emrm.load_results wraps it).");
  m.def(
      "merge",
      [](const std::vector<py::object>& dirs, py::handle output_dir) {
        std::vector<std::filesystem::path> paths;
        for (const auto& d : dirs) paths.push_back(to_path(d));
        campaign::merge(paths, to_path(output_dir));
      },
      py::arg("dirs"), py::arg("output_dir"),
      "Joins the results folders of the shards of one campaign into output_dir, as `emrm merge` does.");
}

}  // namespace emrm::python
