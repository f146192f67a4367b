// The step's extents and the ordered list of checks (step.hpp).

#include "emrm/sim/step.hpp"

#include <algorithm>

#include "check_support.hpp"

namespace emrm::sim {

Extent extent_of(const core::OrientedBox& box) noexcept {
  Extent e{detail::kInfinity, -detail::kInfinity, detail::kInfinity, -detail::kInfinity};
  for (const auto& c : box.corners()) {
    e.min_x = std::min(e.min_x, c.x);
    e.max_x = std::max(e.max_x, c.x);
    e.min_y = std::min(e.min_y, c.y);
    e.max_y = std::max(e.max_y, c.y);
  }
  return e;
}

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
