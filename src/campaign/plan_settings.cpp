#include "emrm/campaign/plan_settings.hpp"

#include <fmt/format.h>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::campaign {
namespace {

namespace fs = std::filesystem;

// A JSON value of the expected kind, or an InputError naming the key.
const nlohmann::json& member(const nlohmann::json& object, const char* key, const std::string& file,
                             nlohmann::json::value_t type) {
  static const nlohmann::json kNull;
  const auto it = object.find(key);
  if (it == object.end()) return kNull;
  const bool number = type == nlohmann::json::value_t::number_float;
  if (number ? !it->is_number() : it->type() != type)
    throw InputError({file, 1, 1}, fmt::format("'{}' has the wrong type in a scenarios.json", key));
  return *it;
}

// A plan cell's bins: its "levels" object, factor → bin label, in the file's order.
std::vector<std::pair<std::string, std::string>> cell_levels(const nlohmann::json& cell, const std::string& file) {
  std::vector<std::pair<std::string, std::string>> out;
  const auto& levels = member(cell, "levels", file, nlohmann::json::value_t::object);
  if (!levels.is_object()) return out;
  for (const auto& [factor, label] : levels.items()) {
    if (!label.is_string()) throw InputError({file, 1, 1}, "'levels' of a cell must map factors to bin labels");
    out.emplace_back(factor, label.get<std::string>());
  }
  return out;
}

// The plan's modes and its shortfalls (objects, or the text of plans written before they had kinds).
void read_plan_modes(const nlohmann::json& j, const std::string& file, PlanSettings& s) {
  if (const auto& modes = member(j, "malfunctions", file, nlohmann::json::value_t::array); modes.is_array())
    for (const auto& m : modes)
      if (m.is_object() && m.contains("id") && m["id"].is_string())
        s.malfunctions.push_back(m["id"].get<std::string>());
  const auto& stop = member(j, "stop", file, nlohmann::json::value_t::object);
  if (!stop.is_object()) return;
  if (const auto& list = member(stop, "shortfalls", file, nlohmann::json::value_t::array); list.is_array())
    for (const auto& item : list) {
      if (item.is_string())
        s.shortfalls.push_back({"", "", item.get<std::string>()});
      else if (item.is_object())
        s.shortfalls.push_back({item.value("kind", ""), item.value("subject", ""), item.value("message", "")});
      else
        throw InputError({file, 1, 1}, "'stop.shortfalls' must list shortfalls (objects or text)");
    }
}

}  // namespace

std::string default_acceptance_strategy() {
  const sim::StrategyTable strategies = sim::registered_strategies();
  const sim::StrategyInfo* chooser = strategies.first_of(sim::StrategyRole::kChooser);
  return chooser != nullptr ? chooser->name : std::string();
}

PlanSettings read_plan_settings(const fs::path& scenarios_json) {
  const std::string file = scenarios_json.string();
  const std::string text = core::read_input_file(scenarios_json);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError({file, 1, static_cast<int>(e.byte)}, fmt::format("not valid JSON: {}", e.what()));
  } catch (const nlohmann::json::exception& e) {  // a number too large for a double: 1e999
    throw InputError({file, 1, 1}, fmt::format("not valid JSON: {}", e.what()));
  }
  if (!j.is_object()) throw InputError({file, 1, 1}, "expected a scenarios.json object (odd, settings, scenarios)");
  PlanSettings s;
  const auto& odd = member(j, "odd", file, nlohmann::json::value_t::object);
  const auto& settings = member(j, "settings", file, nlohmann::json::value_t::object);
  if (odd.is_object()) {
    if (const auto& v = member(odd, "safety", file, nlohmann::json::value_t::string); v.is_string())
      s.safety_file = v.get<std::string>();
    if (const auto& v = member(odd, "scene", file, nlohmann::json::value_t::string); v.is_string())
      s.scene_file = v.get<std::string>();
  }
  if (settings.is_object()) {
    if (const auto& v = member(settings, "strategies", file, nlohmann::json::value_t::array); v.is_array())
      for (const auto& name : v) {
        if (!name.is_string()) throw InputError({file, 1, 1}, "'strategies' must list strategy names");
        try {
          sim::validate_strategy(name.get<std::string>());
        } catch (const UsageError& e) {
          throw InputError({file, 1, 1}, e.what());
        }
        s.strategies.push_back(name.get<std::string>());
      }
    if (const auto& a = member(settings, "acceptance", file, nlohmann::json::value_t::object); a.is_object()) {
      if (const auto& v = member(a, "strategy", file, nlohmann::json::value_t::string); v.is_string())
        s.acceptance_strategy = v.get<std::string>();
      if (const auto& v = member(a, "outcome", file, nlohmann::json::value_t::string); v.is_string())
        s.acceptance_outcome = v.get<std::string>();
    }
    if (const auto& v = member(settings, "delta", file, nlohmann::json::value_t::number_float); v.is_number())
      s.delta = v.get<double>();
    if (const auto& v = member(settings, "epsilon", file, nlohmann::json::value_t::number_float); v.is_number())
      s.epsilon = v.get<double>();
    if (const auto& v = member(settings, "seed", file, nlohmann::json::value_t::number_float); v.is_number()) {
      // A float or a negative number would convert with undefined behaviour or wrap around.
      if (!v.is_number_unsigned())
        throw InputError({file, 1, 1}, fmt::format("settings.seed: expected a whole number from 0 to 2^64 - 1, got {}",
                                                   v.dump().substr(0, 40)));
      s.seed = v.get<std::uint64_t>();
    }
  }
  if (const auto& factors = member(j, "factors", file, nlohmann::json::value_t::array); factors.is_array()) {
    // Read through the factors' own field list (JSON is YAML: errors name their line and column).
    const auto node = core::YamlNode::parse(text, file).at("factors");
    core::YamlCodec<std::vector<scenario::PlanFactor>>::read(node, s.factors.emplace());
  }
  read_plan_modes(j, file, s);
  if (const auto& cells = member(j, "cells", file, nlohmann::json::value_t::array); cells.is_array())
    for (const auto& c : cells) {
      if (!c.is_object() || !c.contains("cell") || !c["cell"].is_string()) continue;
      const std::string key = c["cell"].get<std::string>();
      if (const auto t = c.find("tracked"); t != c.end() && t->is_boolean() && t->get<bool>())
        s.tracked_cells.insert(key);
      s.cell_levels[key] = cell_levels(c, file);
    }
  // Paths in a scenarios.json are relative to its own folder.
  for (auto* p : {&s.safety_file, &s.scene_file})
    if (*p && (*p)->is_relative()) *p = scenarios_json.parent_path() / **p;
  if (s.acceptance_strategy.empty()) s.acceptance_strategy = default_acceptance_strategy();
  try {
    sim::validate_strategy(s.acceptance_strategy);
  } catch (const UsageError& e) {
    throw InputError({file, 1, 1}, fmt::format("acceptance strategy: {}", e.what()));
  }
  if (s.acceptance_outcome != "avoided" && s.acceptance_outcome != "mitigated")
    throw InputError({file, 1, 1},
                     fmt::format("acceptance outcome must be avoided or mitigated, got '{}'", s.acceptance_outcome));
  if (!(s.epsilon > 0.0 && s.epsilon < 0.5))
    throw InputError({file, 1, 1},
                     fmt::format("settings.epsilon: expected a half-width in (0, 0.5), got {:g}", s.epsilon));
  if (!(s.delta > 0.0 && s.delta < 1.0))
    throw InputError({file, 1, 1}, fmt::format("delta must lie in (0, 1), got {:g}", s.delta));
  return s;
}

}  // namespace emrm::campaign
