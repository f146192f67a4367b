#include "emrm/safety/checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "emrm/safety/asil.hpp"

namespace emrm::safety {
namespace {

class Checker {
 public:
  Checker(const SafetyCase& sc, const std::optional<FsmTransitions>& fsm) : sc_(sc), fsm_(fsm) {}

  std::vector<Finding> run() {
    check_hazards();
    check_losses_reached();
    check_control_actions();
    check_ucas();
    std::stable_sort(findings_.begin(), findings_.end(), [](const Finding& a, const Finding& b) {
      return std::pair(a.where.line, a.where.column) < std::pair(b.where.line, b.where.column);
    });
    return std::move(findings_);
  }

 private:
  void add(std::string code, FindingSeverity severity, std::string subject, std::string message, SourceLocation where) {
    findings_.push_back({std::move(code), severity, std::move(subject), std::move(message), std::move(where)});
  }

  void check_hazards() {
    for (const auto& h : sc_.hazards) {
      if (h.losses.empty())
        add("SAF002", FindingSeverity::kError, h.id, fmt::format("hazard '{}' leads to no loss", h.id), h.where);
      for (const auto& ref : h.losses)
        if (!sc_.find_loss(ref.id))
          add("SAF001", FindingSeverity::kError, h.id,
              fmt::format("hazard '{}' refers to loss '{}', which does not exist", h.id, ref.id), ref.where);
      const Asil computed = determine_asil(h);
      if (h.asil && *h.asil != computed)
        add("SAF006", FindingSeverity::kError, h.id,
            fmt::format("hazard '{}' states ASIL {} but {} {} {} give ASIL {} (ISO 26262-3 Table 4)", h.id,
                        core::enum_name(*h.asil), core::enum_name(h.severity), core::enum_name(h.exposure),
                        core::enum_name(h.controllability), core::enum_name(computed)),
            h.where);
      if (h.smil && sc_.smil) {
        if (const SmilRule* rule = find_smil_rule(*sc_.smil, h); !rule)
          add("SAF010", FindingSeverity::kWarning, h.id,
              fmt::format("hazard '{}' states SMIL {} but no rule of the SMIL table matches its ratings", h.id,
                          *h.smil),
              h.where);
        else if (rule->smil != *h.smil)
          add("SAF009", FindingSeverity::kError, h.id,
              fmt::format("hazard '{}' states SMIL {} but the SMIL table (rule at {}) gives {}", h.id, *h.smil,
                          rule->where.str(), rule->smil),
              h.where);
      }
    }
  }

  void check_losses_reached() {
    for (const auto& l : sc_.losses) {
      const bool reached = std::any_of(sc_.hazards.begin(), sc_.hazards.end(), [&](const Hazard& h) {
        return std::any_of(h.losses.begin(), h.losses.end(), [&](const Ref& r) { return r.id == l.id; });
      });
      if (!reached)
        add("SAF003", FindingSeverity::kWarning, l.id, fmt::format("no hazard leads to loss '{}'", l.id), l.where);
    }
  }

  void check_control_actions() {
    for (const auto& ca : sc_.control_actions) {
      for (UcaType type : kAllUcaTypes) {
        const bool present = std::any_of(sc_.ucas.begin(), sc_.ucas.end(),
                                         [&](const Uca& u) { return u.control_action.id == ca.id && u.type == type; });
        if (!present)
          add("SAF005", FindingSeverity::kWarning, ca.id,
              fmt::format("control action '{}' has no UCA of type {}", ca.id, core::enum_name(type)), ca.where);
      }
    }
  }

  void check_ucas() {
    for (const auto& u : sc_.ucas) {
      if (!sc_.find_control_action(u.control_action.id))
        add("SAF001", FindingSeverity::kError, u.id,
            fmt::format("UCA '{}' refers to control action '{}', which does not exist", u.id, u.control_action.id),
            u.control_action.where);
      if (u.hazards.empty())
        add("SAF004", FindingSeverity::kError, u.id, fmt::format("UCA '{}' leads to no hazard", u.id), u.where);
      for (const auto& ref : u.hazards)
        if (!sc_.find_hazard(ref.id))
          add("SAF001", FindingSeverity::kError, u.id,
              fmt::format("UCA '{}' refers to hazard '{}', which does not exist", u.id, ref.id), ref.where);
      if (u.fsm_transitions.empty())
        add("SAF007", FindingSeverity::kError, u.id, fmt::format("UCA '{}' names no FSM transition", u.id), u.where);
      if (!u.region)
        add("SAF008", FindingSeverity::kError, u.id, fmt::format("UCA '{}' has no hazard region", u.id), u.where);
      if (fsm_)
        for (const auto& t : u.fsm_transitions)
          if (!fsm_->transitions.contains({t.from.id, t.event.id, t.to.id}))
            add("SAF011", FindingSeverity::kError, u.id,
                fmt::format("UCA '{}' names transition {}, which the FSM in {} does not have", u.id, t.str(),
                            fsm_->file),
                t.where);
    }
  }

  const SafetyCase& sc_;
  const std::optional<FsmTransitions>& fsm_;
  std::vector<Finding> findings_;
};

}  // namespace

std::vector<Finding> check(const SafetyCase& sc, const std::optional<FsmTransitions>& fsm) {
  return Checker(sc, fsm).run();
}

std::size_t count(const std::vector<Finding>& findings, FindingSeverity severity) {
  return static_cast<std::size_t>(
      std::count_if(findings.begin(), findings.end(), [&](const Finding& f) { return f.severity == severity; }));
}

}  // namespace emrm::safety
