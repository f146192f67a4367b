// The registry of scenario families (family.hpp): the shipped ones, then whatever a program or a
// test registers.

#include "emrm/sim/family.hpp"

#include <fmt/format.h>

#include "emrm/core/error.hpp"
#include "emrm/core/registry.hpp"
#include "emrm/sim/crossing.hpp"
#include "emrm/sim/cut_in.hpp"
#include "emrm/sim/highway.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {
namespace {

core::Registry<ScenarioFamilyInfo>& family_registry() {
  static core::Registry<ScenarioFamilyInfo> families(
      "scenario family", {tjunction_family(), highway_obstacle_family(), pedestrian_crossing_family(), cut_in_family()},
      [](const ScenarioFamilyInfo& f) -> std::string_view { return f.name; });
  return families;
}

}  // namespace

FamilyRegistration::FamilyRegistration(ScenarioFamilyInfo info) : name_(info.name) {
  if (!info.factors || !info.layout)
    throw UsageError(fmt::format("scenario family '{}' needs its factors and its layout", info.name));
  family_registry().add(std::move(info));
}

FamilyRegistration::~FamilyRegistration() { family_registry().remove(name_); }

std::shared_ptr<const ScenarioFamilyInfo> find_family(std::string_view name) {
  auto table = family_registry().table();
  for (const auto& f : *table)
    if (f.name == name) return {table, &f};  // shares the table's ownership
  throw UsageError(fmt::format("unknown scenario family '{}' (known: {})", name, fmt::join(family_names(), ", ")));
}

std::vector<std::string> family_names() { return family_registry().names(); }

std::vector<std::shared_ptr<const ScenarioFamilyInfo>> registered_families() {
  auto table = family_registry().table();
  std::vector<std::shared_ptr<const ScenarioFamilyInfo>> out;
  out.reserve(table->size());
  for (const auto& f : *table) out.emplace_back(table, &f);
  return out;
}

bool has_tjunction_analytics(const SceneConfig& config) { return find_family(config.family)->tjunction_analytics; }

}  // namespace emrm::sim
