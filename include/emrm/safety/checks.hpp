#pragma once

// Consistency checks of a safety case (docs/safety-yaml.md, "Findings"). Each finding has a stable code, a
// severity and the place in the file it concerns. Codes (see docs/safety-yaml.md):
//   SAF001 error    a reference names an id that does not exist (or of the wrong kind)
//   SAF002 error    a hazard leads to no loss
//   SAF003 warning  a loss no hazard leads to
//   SAF004 error    a UCA leads to no hazard
//   SAF005 warning  a control action has no UCA of one of the four STPA types
//   SAF006 error    a stated ASIL disagrees with the one S/E/C give
//   SAF007 error    a UCA names no FSM transition
//   SAF008 error    a UCA has no hazard region
//   SAF009 error    a stated SMIL disagrees with the SMIL table
//   SAF010 warning  a hazard states a SMIL but no rule of the table matches its ratings
//   SAF011 error    a UCA names an FSM transition the EMRM FSM does not have

#include <array>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "emrm/safety/model.hpp"

namespace emrm::safety {

enum class FindingSeverity { kError, kWarning };

struct Finding {
  std::string code;  ///< stable, e.g. "SAF001"
  FindingSeverity severity = FindingSeverity::kError;
  std::string subject;  ///< id of the entity concerned
  std::string message;
  SourceLocation where;

  /// The finding's fields as findings.json lists them (file, line and column of `where` flat):
  /// for its writer (findings_json) and its reader (read_findings_json).
  template <class A>
  void serialize(A& a) {
    a.required("code", code);
    a.required("severity", severity);
    a.required("subject", subject);
    a.required("message", message);
    a.required("file", where.file);
    a.required("line", where.line);
    a.required("column", where.column);
  }
};

/// The transitions of the EMRM FSM that UCAs may refer to, and the file they come from.
struct FsmTransitions {
  std::string file;
  std::set<std::array<std::string, 3>> transitions;  ///< {from, event, to}
};

/// Runs every check; findings come in the order of the file. With `fsm`, UCA transitions are
/// also checked against it (SAF011).
[[nodiscard]] std::vector<Finding> check(const SafetyCase& sc, const std::optional<FsmTransitions>& fsm = {});

/// Number of findings of the given severity.
[[nodiscard]] std::size_t count(const std::vector<Finding>& findings, FindingSeverity severity);

}  // namespace emrm::safety

namespace emrm::core {
template <>
struct EnumNames<safety::FindingSeverity> {
  static constexpr std::array kNames{std::pair{safety::FindingSeverity::kError, std::string_view("error")},
                                     std::pair{safety::FindingSeverity::kWarning, std::string_view("warning")}};
};
}  // namespace emrm::core
