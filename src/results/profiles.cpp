#include "emrm/results/profiles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/sim/json.hpp"

namespace emrm::results {
namespace {

namespace fs = std::filesystem;

}  // namespace

std::vector<fs::path> scene_profiles(const campaign::Campaign& campaign) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(campaign::scene_folder(campaign) / "profiles", ec))
    if (entry.is_regular_file() && entry.path().extension() == ".yaml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

void write_profile_index(const fs::path& dir, const std::vector<ProfileRun>& runs) {
  nlohmann::ordered_json index = nlohmann::ordered_json::array();
  for (const auto& run : runs)
    index.push_back({{"name", run.name},
                     {"description", run.description},
                     {"actuation", sim::to_json(run.actuation)},
                     {"store", run.store.generic_string()},
                     {"reused", run.reused}});
  core::write_file(ResultsDir(dir).profile_index_json(), index.dump(2) + "\n");
}

std::vector<ProfileRun> read_profile_index(const fs::path& dir) {
  const fs::path file = ResultsDir(dir).profile_index_json();
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return {};
  std::vector<ProfileRun> runs;
  try {
    const auto index = nlohmann::json::parse(core::read_input_file(file));
    for (const auto& e : index) {
      ProfileRun run;
      run.name = e.at("name").get<std::string>();
      run.description = e.at("description").get<std::string>();
      run.actuation = sim::actuation_from_json(e.at("actuation"), file.string() + ": " + run.name);
      run.store = e.at("store").get<std::string>();
      run.reused = e.at("reused").get<bool>();
      runs.push_back(std::move(run));
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError({file.string(), 1, 1}, fmt::format("not a profile index written by emrm reproduce: {}", e.what()));
  }
  return runs;
}

core::Table profiles_table(const std::vector<ProfileRun>& runs,
                           const std::vector<std::vector<campaign::CellRecord>>& records, const PaperReference& paper,
                           const std::string& grid) {
  core::Table t;
  t.title = fmt::format("Regions of grid '{}' under each actuation profile (percent of feasible cells)", grid);
  t.header = {"profile", "actuation", "feasible", "G (%)", "Y (%)", "O (%)", "R (%)", "O/R certified", "O/R undecided"};
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RegionCounts c = count_regions(records[i], grid);
    std::size_t certified = 0, undecided = 0;
    for (const auto& r : records[i]) {
      if (r.grid != grid || !r.feasible || (r.region != sim::Region::kO && r.region != sim::Region::kR)) continue;
      certified += r.evidence == campaign::CellEvidence::kCertificate;
      undecided += r.evidence == campaign::CellEvidence::kUndecided;
    }
    t.rows.push_back({runs[i].name + (runs[i].reused ? " (this scene)" : ""), runs[i].actuation.summary(),
                      std::to_string(c.feasible), core::format_number(c.pct(c.g), 1),
                      core::format_number(c.pct(c.y), 1), core::format_number(c.pct(c.o), 1),
                      core::format_number(c.pct(c.r), 1), std::to_string(certified), std::to_string(undecided)});
  }
  if (paper.fine_grid.grid == grid) {
    const auto& p = paper.fine_grid.regions_pct;
    t.rows.push_back({"the paper's map", "its own model, not stated", std::to_string(paper.fine_grid.feasible_cells),
                      core::format_number(p.g, 1), core::format_number(p.y, 1), core::format_number(p.o, 1),
                      core::format_number(p.r, 1), std::string(core::kNoValue), std::string(core::kNoValue)});
  }
  t.notes.push_back(
      "Each profile overlays the scene's actuation (examples/tjunction/profiles/, docs/actuation.md); every other "
      "setting, the cells and the seeds are the same. G moves with the stop's closed form (perception latency, brake "
      "dead time, ramp, cap); Y, O and R also with the steering actuator, which delays and slows every evasive "
      "maneuver. The `paper` profile is fitted by `emrm calibrate --regions` to the paper's G alone, so its G matches "
      "by construction and its Y, O and R are the test of the explanation.");
  return t;
}

}  // namespace emrm::results
