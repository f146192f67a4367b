#include "emrm/sim/planner.hpp"

#include <algorithm>
#include <limits>

#include "emrm/core/registry.hpp"

namespace emrm::sim {
namespace {

using PlannerPtr = std::shared_ptr<const Planner>;

core::Registry<PlannerPtr>& registry() {
  static core::Registry<PlannerPtr> planners("planner",
                                             {std::make_shared<RrtPlanner>(), std::make_shared<ReferencePlanner>()},
                                             [](const PlannerPtr& p) { return p->name(); });
  return planners;
}

}  // namespace

const Planner* find_planner(std::string_view name) {
  // Entries are never destroyed while registered, and registrations outlive the simulations that
  // use them (see PlannerRegistration), so the pointer stays valid for its user.
  for (const auto& p : *registry().table())
    if (p->name() == name) return p.get();
  return nullptr;
}

std::vector<std::string> planner_names() {
  std::vector<std::string> names;
  for (const auto& p : *registry().table()) names.emplace_back(p->name());
  return names;
}

PlannerRegistration::PlannerRegistration(std::unique_ptr<Planner> planner) : name_(planner->name()) {
  registry().add(PlannerPtr(std::move(planner)));
}

PlannerRegistration::~PlannerRegistration() { registry().remove(name_); }

double lateral_miss_m(const Scene& scene, const RolloutResult& rollout) noexcept {
  if (rollout.passed_truck) return 0.0;
  if (rollout.termination != Termination::kContact) return std::numeric_limits<double>::infinity();
  double highest = -std::numeric_limits<double>::infinity();
  for (const auto& corner : scene.ego_box(rollout.end_state).corners()) highest = std::max(highest, corner.y);
  return std::max(0.0, highest - scene.truck_front_y_at(rollout.end_time_s));
}

bool less_loss(const ImpactAssessment& a, const ImpactAssessment& b) noexcept {
  if (a.loss_level != b.loss_level) return a.loss_level < b.loss_level;
  return a.delta_v_mps < b.delta_v_mps;
}

}  // namespace emrm::sim
