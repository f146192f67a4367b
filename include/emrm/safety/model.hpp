#pragma once

// The safety case as data (paper §III-B, §IV; docs/safety-yaml.md): losses, hazards with their HARA
// and extended ratings, control actions, unsafe control actions (UCAs) and the SMIL lookup
// table. Entities have stable string ids and refer to each other only by id; each entity and
// each reference remembers where it was written, so findings can point into the file.

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/core/expression.hpp"
#include "emrm/core/yaml.hpp"

namespace emrm::safety {

enum class Severity { kS0, kS1, kS2, kS3 };
enum class Exposure { kE0, kE1, kE2, kE3, kE4 };
enum class Controllability { kC0, kC1, kC2, kC3 };
enum class Asil { kQM, kA, kB, kC, kD };
/// The paper's extended ratings (HARA*): maneuverability M1–M3, avoidability A1–A3,
/// mitigability 𝓜1–𝓜3 (written MT1–MT3 in YAML).
enum class Maneuverability { kM1, kM2, kM3 };
enum class Avoidability { kA1, kA2, kA3 };
enum class Mitigability { kMT1, kMT2, kMT3 };
/// The four STPA ways a control action can be unsafe.
enum class UcaType { kNotProvided, kProvided, kWrongTimingOrOrder, kStoppedTooSoonOrAppliedTooLong };
inline constexpr std::array<UcaType, 4> kAllUcaTypes{
    UcaType::kNotProvided, UcaType::kProvided, UcaType::kWrongTimingOrOrder, UcaType::kStoppedTooSoonOrAppliedTooLong};

using core::Ref;

/// A reference to a transition of the hazard–loss FSM (docs/fsm.md).
using core::TransitionRef;

/// An operational-design-domain factor that hazard regions may name (e.g. `ttc_s`).
struct Factor {
  std::string name;
  std::string unit;
  std::string description;
  std::optional<double> min;
  std::optional<double> max;
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("name", name);
    a.optional("unit", unit);
    a.optional("description", description);
    a.optional("min", min);
    a.optional("max", max);
  }
};

struct Loss {
  std::string id;
  std::string name;
  std::string description;
  bool reversible = true;  ///< L1–L5 reversible, L6–L7 irreversible in the paper
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("id", id);
    a.required("name", name);
    a.optional("description", description);
    a.required("reversible", reversible);
  }
};

struct Hazard {
  std::string id;
  std::string description;
  std::vector<Ref> losses;
  Severity severity = Severity::kS0;
  Exposure exposure = Exposure::kE0;
  Controllability controllability = Controllability::kC0;
  std::optional<Asil> asil;  ///< as stated by the author; checked against S/E/C
  std::optional<Maneuverability> maneuverability;
  std::optional<Avoidability> avoidability;
  std::optional<Mitigability> mitigability;
  std::optional<std::string> smil;  ///< as stated by the author; checked against the SMIL table
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("id", id);
    a.required("description", description);
    a.required("losses", losses);
    a.required("severity", severity);
    a.required("exposure", exposure);
    a.required("controllability", controllability);
    a.optional("asil", asil);
    a.optional("maneuverability", maneuverability);
    a.optional("avoidability", avoidability);
    a.optional("mitigability", mitigability);
    a.optional("smil", smil);
  }
};

struct ControlAction {
  std::string id;
  std::string controller;
  std::string action;
  std::string controlled_process;
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("id", id);
    a.required("controller", controller);
    a.required("action", action);
    a.required("controlled_process", controlled_process);
  }
};

struct Uca {
  std::string id;
  Ref control_action;
  UcaType type = UcaType::kNotProvided;
  std::string context;
  std::vector<Ref> hazards;
  std::vector<TransitionRef> fsm_transitions;
  std::optional<std::string> region;                  ///< predicate over the declared factors
  std::optional<core::Expression> region_expression;  ///< compiled at load time
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("id", id);
    a.required("control_action", control_action);
    a.required("type", type);
    a.required("context", context);
    a.optional("hazards", hazards);
    a.optional("fsm_transitions", fsm_transitions);
    a.optional("region", region);
  }
};

/// One row of the SMIL lookup table: the ratings it matches (absent = any) and its level.
struct SmilRule {
  std::optional<Severity> severity;
  std::optional<Exposure> exposure;
  std::optional<Controllability> controllability;
  std::optional<Asil> asil;
  std::optional<Maneuverability> maneuverability;
  std::optional<Avoidability> avoidability;
  std::optional<Mitigability> mitigability;
  std::string smil;
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.optional("severity", severity);
    a.optional("exposure", exposure);
    a.optional("controllability", controllability);
    a.optional("asil", asil);
    a.optional("maneuverability", maneuverability);
    a.optional("avoidability", avoidability);
    a.optional("mitigability", mitigability);
    a.required("smil", smil);
  }
};

/// The SMIL lookup: ordered rules, first match wins. Its levels are the safety case's own.
struct SmilTable {
  std::vector<std::string> levels;
  std::vector<SmilRule> rules;
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("levels", levels);
    a.required("rules", rules);
  }
};

/// A whole safety case, as read from one YAML file.
struct SafetyCase {
  std::string name;
  std::string description;
  std::optional<std::string> fsm;  ///< path of the EMRM FSM file, relative to the safety file
  std::vector<Factor> factors;
  std::vector<Loss> losses;
  std::vector<Hazard> hazards;
  std::vector<ControlAction> control_actions;
  std::vector<Uca> ucas;
  std::optional<SmilTable> smil;
  std::string file;  ///< where it was loaded from

  template <class A>
  void serialize(A& a) {
    a.required("name", name);
    a.optional("description", description);
    a.optional("fsm", fsm);
    a.optional("factors", factors);
    a.required("losses", losses);
    a.required("hazards", hazards);
    a.required("control_actions", control_actions);
    a.required("ucas", ucas);
    a.optional("smil", smil);
  }

  [[nodiscard]] const Loss* find_loss(std::string_view id) const;
  [[nodiscard]] const Hazard* find_hazard(std::string_view id) const;
  [[nodiscard]] const ControlAction* find_control_action(std::string_view id) const;
  [[nodiscard]] const Uca* find_uca(std::string_view id) const;
  /// Names of the declared factors, in file order (the variables of every region).
  [[nodiscard]] std::vector<std::string> factor_names() const;
};

}  // namespace emrm::safety

namespace emrm::core {

template <>
struct EnumNames<safety::Severity> {
  static constexpr std::array kNames{std::pair{safety::Severity::kS0, std::string_view("S0")},
                                     std::pair{safety::Severity::kS1, std::string_view("S1")},
                                     std::pair{safety::Severity::kS2, std::string_view("S2")},
                                     std::pair{safety::Severity::kS3, std::string_view("S3")}};
};
template <>
struct EnumNames<safety::Exposure> {
  static constexpr std::array kNames{std::pair{safety::Exposure::kE0, std::string_view("E0")},
                                     std::pair{safety::Exposure::kE1, std::string_view("E1")},
                                     std::pair{safety::Exposure::kE2, std::string_view("E2")},
                                     std::pair{safety::Exposure::kE3, std::string_view("E3")},
                                     std::pair{safety::Exposure::kE4, std::string_view("E4")}};
};
template <>
struct EnumNames<safety::Controllability> {
  static constexpr std::array kNames{std::pair{safety::Controllability::kC0, std::string_view("C0")},
                                     std::pair{safety::Controllability::kC1, std::string_view("C1")},
                                     std::pair{safety::Controllability::kC2, std::string_view("C2")},
                                     std::pair{safety::Controllability::kC3, std::string_view("C3")}};
};
template <>
struct EnumNames<safety::Asil> {
  static constexpr std::array kNames{
      std::pair{safety::Asil::kQM, std::string_view("QM")}, std::pair{safety::Asil::kA, std::string_view("A")},
      std::pair{safety::Asil::kB, std::string_view("B")}, std::pair{safety::Asil::kC, std::string_view("C")},
      std::pair{safety::Asil::kD, std::string_view("D")}};
};
template <>
struct EnumNames<safety::Maneuverability> {
  static constexpr std::array kNames{std::pair{safety::Maneuverability::kM1, std::string_view("M1")},
                                     std::pair{safety::Maneuverability::kM2, std::string_view("M2")},
                                     std::pair{safety::Maneuverability::kM3, std::string_view("M3")}};
};
template <>
struct EnumNames<safety::Avoidability> {
  static constexpr std::array kNames{std::pair{safety::Avoidability::kA1, std::string_view("A1")},
                                     std::pair{safety::Avoidability::kA2, std::string_view("A2")},
                                     std::pair{safety::Avoidability::kA3, std::string_view("A3")}};
};
template <>
struct EnumNames<safety::Mitigability> {
  static constexpr std::array kNames{std::pair{safety::Mitigability::kMT1, std::string_view("MT1")},
                                     std::pair{safety::Mitigability::kMT2, std::string_view("MT2")},
                                     std::pair{safety::Mitigability::kMT3, std::string_view("MT3")}};
};
template <>
struct EnumNames<safety::UcaType> {
  static constexpr std::array kNames{
      std::pair{safety::UcaType::kNotProvided, std::string_view("not_provided")},
      std::pair{safety::UcaType::kProvided, std::string_view("provided")},
      std::pair{safety::UcaType::kWrongTimingOrOrder, std::string_view("wrong_timing_or_order")},
      std::pair{safety::UcaType::kStoppedTooSoonOrAppliedTooLong,
                std::string_view("stopped_too_soon_or_applied_too_long")}};
};

}  // namespace emrm::core
