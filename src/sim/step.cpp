// The ordered list of checks (step.hpp).

#include "emrm/sim/step.hpp"

#include "check_support.hpp"

namespace emrm::sim {

CheckList& CheckList::add(std::unique_ptr<StepCheck> check) {
  checks_.push_back(std::move(check));
  return *this;
}

bool CheckList::ends(Step& step, RolloutResult& result, Termination& why) const {
  for (const auto& c : checks_)
    if (const auto answer = c->check(step, result)) return detail::end(why, *answer);
  return false;
}

std::optional<Termination> CheckList::check(Step& step, RolloutResult& result) const {
  return detail::answer_of(*this, step, result);
}

}  // namespace emrm::sim
