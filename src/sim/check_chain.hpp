#pragma once

// The members of CheckChain (step.hpp) that need its built-in checks complete. Internal to src/sim:
// included by the .cpp of each checker (validity.cpp, termination.cpp), after its BuiltIn struct,
// which then instantiates the template for itself.

#include <memory>
#include <optional>
#include <utility>

#include "check_support.hpp"
#include "emrm/sim/step.hpp"

namespace emrm::sim {

template <class Checker, class BuiltIn>
CheckChain<Checker, BuiltIn>::CheckChain(std::unique_ptr<const BuiltIn> built_in) : built_in_(std::move(built_in)) {}
template <class Checker, class BuiltIn>
CheckChain<Checker, BuiltIn>::~CheckChain() = default;
template <class Checker, class BuiltIn>
CheckChain<Checker, BuiltIn>::CheckChain(CheckChain&&) noexcept = default;
template <class Checker, class BuiltIn>
CheckChain<Checker, BuiltIn>& CheckChain<Checker, BuiltIn>::operator=(CheckChain&&) noexcept = default;

template <class Checker, class BuiltIn>
bool CheckChain<Checker, BuiltIn>::ends(Step& step, RolloutResult& result, Termination& why) const {
  return built_in_->ends(step, result, why) || (!added_.empty() && added_.ends(step, result, why));
}

template <class Checker, class BuiltIn>
std::optional<Termination> CheckChain<Checker, BuiltIn>::check(Step& step, RolloutResult& result) const {
  return detail::answer_of(*this, step, result);
}

}  // namespace emrm::sim
