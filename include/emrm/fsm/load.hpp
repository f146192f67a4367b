#pragma once

// Reading generators and traces from files. The FSM YAML schema (docs/fsm.md):
//
//   name: emrm                         # required, text
//   description: ...                   # optional, text
//   states:                            # required list; each a mapping or a plain id
//     - {id: S1, description: normal driving}
//   events:                            # required list; each a mapping or a plain id
//     - {id: hazard_detected, description: ...}
//     - no_risk
//   initial: S1                        # required, a declared state
//   marked: [S1, S6]                   # required list (may be empty) of declared states
//   transitions:                       # required list (may be empty)
//     - {from: S1, event: hazard_detected, to: S2}
//
// Ids are made of letters, digits, '_', '-' and '.', so that a word can be written as ids
// separated by spaces and a composed state "a|b" can never be confused with a declared one.
// Two transitions with the same `from` and `event` but different `to` are accepted (the machine
// is then non-deterministic, which `check_deterministic` reports); an identical transition twice
// is an input error.

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/fsm/generator.hpp"

namespace emrm::fsm {

/// Loads a generator from an FSM YAML file. Throws InputError naming file:line:column and what was
/// expected for: an unreadable file, malformed YAML, a wrong type, a missing or unknown field, an
/// invalid, duplicate state or event id, an initial / marked / transition naming an unknown state or
/// event, a state marked twice, and an exact duplicate transition.
[[nodiscard]] Generator load_generator(const std::filesystem::path& path);

/// The same from YAML text; `file_name` is used in error messages.
[[nodiscard]] Generator parse_generator(const std::string& text, const std::string& file_name);

/// One line of a trace file.
struct Trace {
  std::vector<std::string> events;
  SourceLocation where;  ///< file and line (column 1)
};

/// Reads traces: one per line, event ids separated by white space; '#' starts a comment that runs to
/// the end of the line; blank lines are skipped. Throws InputError if the file cannot be read.
[[nodiscard]] std::vector<Trace> load_traces(const std::filesystem::path& path);

/// The same from text; `file_name` is used in locations.
[[nodiscard]] std::vector<Trace> parse_traces(const std::string& text, const std::string& file_name);

}  // namespace emrm::fsm
