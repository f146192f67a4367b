#pragma once

// What `emrm fsm` reports about one generator: the results of the requested operations as one
// value, and the producers of its two printed forms, text and JSON (schema: docs/outputs.md,
// "emrm fsm --format json"). `emrm reproduce` writes the same JSON as its FSM check files
// (write_check_files), so both commands share one writer.

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "emrm/fsm/generator.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/fsm/operations.hpp"

namespace emrm::fsm {

/// A trace file and the traces read from it (load_traces).
struct TraceFile {
  std::string file;  ///< as shown in the report
  std::vector<Trace> traces;
};

/// The operations asked for. All off by default: the report is then the machine's summary alone.
struct ReportRequest {
  bool check = false;                     ///< the four structural checks (check_all)
  int words_max_length = -1;              ///< list L(G) up to this many events; -1: not asked
  std::size_t max_listed_words = 10'000;  ///< beyond this a listing is no longer readable
  std::vector<std::string> word_queries;  ///< words to look up, events separated by spaces
  std::optional<TraceFile> traces;        ///< transition coverage of these traces
};

/// One looked-up word.
struct WordQuery {
  std::string word;  ///< its events joined by single spaces ("" for ε)
  WordEvaluation evaluation;
};

/// Transition coverage of a trace file.
struct TraceCoverageReport {
  TraceFile traces;
  TransitionCoverage coverage;
};

/// The results of the requested operations on one machine.
struct Report {
  Generator machine;
  std::string source;  ///< the FSM file, or "FILE || OTHER" for a composition
  std::optional<CheckReport> check;
  std::optional<WordEnumeration> words;
  std::vector<WordQuery> word_queries;  ///< in the order asked
  std::optional<TraceCoverageReport> coverage;
  std::vector<std::string> written;  ///< files the caller wrote (diagrams); shown last

  /// True when any operation was asked (then the text form leaves the summary out).
  [[nodiscard]] bool has_operations() const noexcept { return check || words || !word_queries.empty() || coverage; }
  /// False when a check failed or a trace is not in L(G): `emrm fsm` then exits 1.
  [[nodiscard]] bool ok() const noexcept {
    return (!check || check->ok()) && (!coverage || coverage->coverage.rejected.empty());
  }
};

/// Runs the operations of `request` on `machine`, each only when asked. Does not throw (a
/// words_max_length below -1 counts as not asked).
[[nodiscard]] Report make_report(Generator machine, std::string source, const ReportRequest& request);

/// The report as `emrm fsm --format json` prints it: {"fsm", "check"?, "words"?, "word_queries"?,
/// "coverage"?, "written"}; only the parts asked for appear, in that order.
[[nodiscard]] nlohmann::ordered_json to_json(const Report& report);

/// The report as `emrm fsm` prints it: the summary when no operation was asked, else the results of
/// each in the JSON's order; then one "wrote FILE" line per written file.
[[nodiscard]] std::string to_text(const Report& report);

/// The machine's DOT diagram (to_dot); with trace coverage, edges carry their counts.
[[nodiscard]] std::string diagram_dot(const Report& report);

/// The check files of `emrm reproduce` for one FSM: DIR/STEM_check.json, byte for byte what
/// `emrm fsm FSM_FILE --check --format json` prints, DIR/STEM_plain.dot (the plain diagram) and,
/// when Graphviz is installed, DIR/STEM_plain.svg, all or none (core::write_files). Returns the
/// check report. Throws InputError for a bad FSM file and emrm::Error when a file cannot be written.
Report write_check_files(const std::filesystem::path& fsm_file, const std::filesystem::path& dir);

}  // namespace emrm::fsm
