#include "emrm/safety/model.hpp"

#include <algorithm>

namespace emrm::safety {
namespace {
template <class T>
const T* find_by_id(const std::vector<T>& items, std::string_view id) {
  auto it = std::find_if(items.begin(), items.end(), [&](const T& item) { return item.id == id; });
  return it == items.end() ? nullptr : &*it;
}
}  // namespace

const Loss* SafetyCase::find_loss(std::string_view id) const { return find_by_id(losses, id); }
const Hazard* SafetyCase::find_hazard(std::string_view id) const { return find_by_id(hazards, id); }
const ControlAction* SafetyCase::find_control_action(std::string_view id) const {
  return find_by_id(control_actions, id);
}
const Uca* SafetyCase::find_uca(std::string_view id) const { return find_by_id(ucas, id); }

std::vector<std::string> SafetyCase::factor_names() const {
  std::vector<std::string> names;
  names.reserve(factors.size());
  for (const auto& f : factors) names.push_back(f.name);
  return names;
}

}  // namespace emrm::safety
