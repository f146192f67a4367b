#pragma once

// A small copy of the shipped T-junction example for end-to-end tests of `emrm reproduce` and
// `emrm report`: the shipped safety case, FSMs, scene and paper reference, with a 3 × 3 campaign
// and a coarse ODD, so that a whole reproduce takes about a second.

#include <filesystem>
#include <string>

#include "run_emrm.hpp"

namespace emrm::e2e {

// Grid fine: speeds 30, 50, 72 × TTCs 0.25, 1.0, 2.0 at mu 1: 7 feasible cells (v·TTC <= 24.5 m);
// grid canonical: two of the twelve validation scenarios, with their trees kept.
inline constexpr const char* kSmallCampaign = R"(scene: scene.yaml
seed: 1
strategies: [emergency_stop, dodge, drift_to_avoid, drift_to_accident, emrm, best_strategy]
grids:
  - name: fine
    speed_kph: [30, 50, 72]
    ttc_s: [0.25, 1.0, 2.0]
    mu: 1.0
    passage_m: 3.0
  - name: canonical
    keep_trees: true
    ttc_s: 1.0
    cells:
      - {name: passage_wide, speed_kph: 43.2, mu: 1.0, passage_m: 3.2}
      - {name: mu_snow, speed_kph: 43.2, mu: 0.35, passage_m: 2.4}
)";

// A coarse ODD over the same corner of the domain: 2 speed × 2 TTC × 2 passage bins, one test per
// tracked cell as precision target, so the planned set stays a handful of scenarios.
inline constexpr const char* kSmallOdd = R"(name: small T-junction ODD
safety: safety.yaml
scene: scene.yaml
seed: 1
factors:
  - {name: speed_kph, bins: [30, 51, 72]}
  - {name: truck_speed_kph, type: constant, value: 10}
  - {name: ttc_s, bins: [0.25, 1.0, 2.0]}
  - {name: mu, type: constant, value: 1.0}
  - {name: passage_m, bins: [1.0, 2.0, 3.0]}
relevance: "speed_kph / 3.6 * ttc_s <= 24.5"
coverage: {strength: 2, n_c: 1, n_m: 1, epsilon: 0.45, delta: 0.05, budget: 40}
baselines:
  manual: {speed_kph: [30, 72], ttc_s: [0.25, 2.0]}
)";

inline std::filesystem::path small_example(const std::string& name) {
  const auto dir = scratch_dir(name) / "example";
  std::filesystem::create_directories(dir);
  for (const char* file :
       {"safety.yaml", "emrm_fsm.yaml", "loss_evaluation_fsm.yaml", "scene.yaml", "paper_reference.yaml"})
    std::filesystem::copy_file(example(file), dir / file);
  std::filesystem::copy(example("profiles"), dir / "profiles");
  write_text(dir / "campaign.yaml", kSmallCampaign);
  write_text(dir / "odd.yaml", kSmallOdd);
  return dir;
}

}  // namespace emrm::e2e
