#include "emrm/safety/asil.hpp"

namespace emrm::safety {

Asil determine_asil(Severity s, Exposure e, Controllability c) noexcept {
  const int si = static_cast<int>(s);
  const int ei = static_cast<int>(e);
  const int ci = static_cast<int>(c);
  if (si == 0 || ei == 0 || ci == 0) return Asil::kQM;
  switch (si + ei + ci) {
    case 10:
      return Asil::kD;
    case 9:
      return Asil::kC;
    case 8:
      return Asil::kB;
    case 7:
      return Asil::kA;
    default:
      return Asil::kQM;
  }
}

namespace {
template <class T>
bool matches(const std::optional<T>& wanted, const std::optional<T>& actual) {
  return !wanted || (actual && *actual == *wanted);
}
template <class T>
bool matches(const std::optional<T>& wanted, const T& actual) {
  return !wanted || actual == *wanted;
}
}  // namespace

const SmilRule* find_smil_rule(const SmilTable& table, const Hazard& h) noexcept {
  for (const auto& rule : table.rules) {
    if (matches(rule.severity, h.severity) && matches(rule.exposure, h.exposure) &&
        matches(rule.controllability, h.controllability) && matches(rule.asil, determine_asil(h)) &&
        matches(rule.maneuverability, h.maneuverability) && matches(rule.avoidability, h.avoidability) &&
        matches(rule.mitigability, h.mitigability))
      return &rule;
  }
  return nullptr;
}

}  // namespace emrm::safety
