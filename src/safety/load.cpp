#include "emrm/safety/load.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "emrm/core/text.hpp"

namespace emrm::safety {
namespace {

// Ids are unique across every kind of entity, so a reference can never be ambiguous.
class IdRegistry {
 public:
  void add(const std::string& id, const SourceLocation& where, std::string_view kind) {
    if (id.empty()) throw InputError(where, fmt::format("expected a non-empty id for this {}", kind));
    auto [it, inserted] = seen_.emplace(id, where);
    if (!inserted)
      throw InputError(where, fmt::format("duplicate id '{}' (first defined at {})", id, it->second.str()));
  }

 private:
  std::map<std::string, SourceLocation> seen_;
};

void validate(SafetyCase& sc, const core::YamlNode& root) {
  IdRegistry ids;
  std::map<std::string, SourceLocation> factor_names;
  for (const auto& f : sc.factors) {
    if (f.name.empty()) throw InputError(f.where, "expected a non-empty factor name");
    if (!factor_names.emplace(f.name, f.where).second)
      throw InputError(f.where, fmt::format("duplicate factor '{}'", f.name));
    if (f.min && f.max && *f.min > *f.max)
      throw InputError(f.where,
                       fmt::format("factor '{}': expected min <= max, got min {} > max {}", f.name, *f.min, *f.max));
  }
  for (const auto& l : sc.losses) ids.add(l.id, l.where, "loss");
  for (const auto& h : sc.hazards) ids.add(h.id, h.where, "hazard");
  for (const auto& c : sc.control_actions) ids.add(c.id, c.where, "control action");

  // Regions are compiled here so that a typo in a predicate is caught at load time, at its column.
  const auto names = sc.factor_names();
  const auto uca_nodes = root.at("ucas").elements();
  for (std::size_t i = 0; i < sc.ucas.size(); ++i) {
    auto& u = sc.ucas[i];
    ids.add(u.id, u.where, "UCA");
    if (u.region) u.region_expression = core::Expression(uca_nodes[i].at("region"), names);
  }

  if (sc.smil) {
    const auto known = [&](const std::string& level) {
      return std::find(sc.smil->levels.begin(), sc.smil->levels.end(), level) != sc.smil->levels.end();
    };
    if (sc.smil->levels.empty()) throw InputError(sc.smil->where, "expected at least one SMIL level in 'levels'");
    for (const auto& rule : sc.smil->rules)
      if (!known(rule.smil))
        throw InputError(rule.where, fmt::format("SMIL level '{}' is not one of the declared levels: {}", rule.smil,
                                                 core::join(sc.smil->levels, ", ")));
    for (const auto& h : sc.hazards)
      if (h.smil && !known(*h.smil))
        throw InputError(h.where, fmt::format("hazard '{}': SMIL level '{}' is not one of the declared levels: {}",
                                              h.id, *h.smil, core::join(sc.smil->levels, ", ")));
  }
}

}  // namespace

SafetyCase parse_safety_case(const std::string& text, const std::string& file_name) {
  const auto root = core::YamlNode::parse(text, file_name);
  SafetyCase sc;
  core::read_yaml(root, sc);
  sc.file = file_name;
  validate(sc, root);
  return sc;
}

SafetyCase load_safety_case(const std::filesystem::path& path) {
  return parse_safety_case(core::read_input_file(path), path.string());
}

std::string to_yaml(const SafetyCase& safety_case) { return core::to_yaml_text(core::write_yaml(safety_case)); }

}  // namespace emrm::safety
