#include "emrm/workflow/profiles.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "emrm/core/error.hpp"
#include "emrm/results/results_dir.hpp"

namespace emrm::workflow {

namespace fs = std::filesystem;
using campaign::GridSpec;
using results::ProfileRun;

std::vector<ProfileRun> sweep_profiles(const campaign::Campaign& campaign, const std::string& grid,
                                       const std::vector<fs::path>& profiles, const campaign::SweepOptions& options) {
  campaign::Campaign one = campaign;
  std::erase_if(one.grids, [&](const campaign::GridSpec& g) { return g.name != grid; });
  if (one.grids.empty()) throw UsageError(fmt::format("the campaign {} has no grid '{}'", campaign.file, grid));
  std::vector<ProfileRun> runs;
  for (const fs::path& file : profiles) {
    ProfileRun run;
    run.name = file.stem().string();
    campaign::Campaign under = one;
    run.description = sim::apply_profile(under.scene, file.string(), file.parent_path());
    run.actuation = under.scene.actuation;
    if (run.actuation == campaign.scene.actuation) {
      run.reused = true;
      run.store = results::ResultsDir().store();  // relative to the folder, as the index keeps it
    } else {
      run.store = results::ResultsDir().profile(run.name).store();
      campaign::SweepOptions o = options;
      o.output_dir = results::ResultsDir(options.output_dir).profile(run.name).root();
      const campaign::SweepSummary s = campaign::sweep(under, o);
      run.simulated = s.cells_simulated;
      run.seconds = s.seconds;
    }
    runs.push_back(std::move(run));
  }
  results::write_profile_index(options.output_dir, runs);
  return runs;
}

}  // namespace emrm::workflow
