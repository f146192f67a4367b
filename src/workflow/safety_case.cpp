#include "emrm/workflow/safety_case.hpp"

#include <utility>

#include "emrm/fsm/load.hpp"
#include "emrm/safety/load.hpp"

namespace emrm::workflow {

safety::Analysis analyze_safety_file(const std::filesystem::path& file,
                                     const std::optional<std::filesystem::path>& fsm_file, bool no_fsm) {
  safety::SafetyCase sc = safety::load_safety_case(file);
  std::optional<safety::FsmTransitions> known;
  const auto path = fsm_file ? fsm_file : safety::fsm_file(sc);
  if (path && !no_fsm) known = safety::fsm_transitions(path->string(), fsm::load_generator(*path).transitions());
  return safety::analyze(std::move(sc), std::move(known));
}

}  // namespace emrm::workflow
