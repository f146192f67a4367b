#include "emrm/sim/planner.hpp"

#include <algorithm>
#include <limits>

#include "emrm/core/registry.hpp"
#include "emrm/sim/falsifier.hpp"

namespace emrm::sim {
namespace {

using PlannerPtr = std::shared_ptr<const Planner>;

core::Registry<PlannerPtr>& planner_registry() {
  static core::Registry<PlannerPtr> planners(
      "planner",
      {std::make_shared<RrtPlanner>(), std::make_shared<ReferencePlanner>(), std::make_shared<FalsifierPlanner>()},
      [](const PlannerPtr& p) { return p->name(); });
  return planners;
}

}  // namespace

const Planner* find_planner(std::string_view name) {
  // Entries are never destroyed while registered, and registrations outlive the simulations that
  // use them (see PlannerRegistration), so the pointer stays valid for its user.
  for (const auto& p : *planner_registry().table())
    if (p->name() == name) return p.get();
  return nullptr;
}

std::vector<std::string> planner_names() { return planner_registry().names(); }

PlannerRegistration::PlannerRegistration(std::unique_ptr<Planner> planner) : name_(planner->name()) {
  planner_registry().add(PlannerPtr(std::move(planner)));
}

PlannerRegistration::~PlannerRegistration() { planner_registry().remove(name_); }

double lateral_miss_m(const Scene& scene, const RolloutResult& rollout) noexcept {
  if (rollout.passed_truck) return 0.0;
  if (rollout.termination != Termination::kContact) return std::numeric_limits<double>::infinity();
  double lowest = std::numeric_limits<double>::infinity();
  double highest = -lowest;
  for (const auto& corner : scene.ego_box(rollout.end_state).corners()) {
    lowest = std::min(lowest, corner.y);
    highest = std::max(highest, corner.y);
  }
  // How far the ego reaches across the hazard's edge beside each free band.
  const FreeBands free = scene.free_bands(rollout.end_time_s);
  double miss = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < free.count; ++i)
    miss = std::min(miss, free.band[i].right ? highest - free.hazard_low_m : free.hazard_high_m - lowest);
  return std::max(0.0, miss);
}

bool less_loss(const ImpactAssessment& a, const ImpactAssessment& b) noexcept {
  if (a.loss_level != b.loss_level) return a.loss_level < b.loss_level;
  // The risks before Δv: a rollover and a pedestrian's injury are not measured in the ego's Δv. For
  // two impacts both risks grow with Δv, so the order is Δv's.
  if (a.p_fatal != b.p_fatal) return a.p_fatal < b.p_fatal;
  if (a.p_mais3 != b.p_mais3) return a.p_mais3 < b.p_mais3;
  return a.delta_v_mps < b.delta_v_mps;
}

}  // namespace emrm::sim
