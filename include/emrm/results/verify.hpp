#pragma once

// `emrm verify`: an independent re-check of a results store (docs/verify.md). Trusts nothing the
// sweep concluded: every stored maneuver is replayed from the cell's initial state and its outcome
// compared with the stored one; every avoidance's trajectory is re-checked every millisecond with
// geometry written apart from the simulator's (no contact, inside the road, a safe state at the
// end); every certificate is re-derived; every region is re-derived from the stored outcomes.

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace emrm::results {

struct VerifyOptions {
  double check_step_s = 0.001;  ///< the avoidances' trajectories are checked at this spacing
  double tolerance_m = 0.001;   ///< overlaps and departures shallower than this are not failures
  int threads = 0;              ///< cells checked side by side on this many threads (0: every core)
};

/// One claim that did not hold.
struct VerifyFailure {
  std::string grid;
  std::int64_t index = 0;
  std::string strategy;  ///< empty for a claim about the cell
  std::string what;
};

struct VerifyReport {
  std::int64_t cells = 0;         ///< feasible cells checked
  std::int64_t witnesses = 0;     ///< maneuvers replayed
  std::int64_t avoidances = 0;    ///< of which avoidances, re-checked every check_step_s
  std::int64_t certificates = 0;  ///< certificates re-derived
  std::int64_t undecided = 0;     ///< cells whose region rests on a search alone
  std::int64_t inferred = 0;      ///< cells an adaptive sweep inferred (their grounds checked, nothing replayed)
  /// Feasible cells by region (G, Y, O, R) and the evidence behind it.
  std::map<std::string, std::map<std::string, std::int64_t>> by_region;
  /// The least distance kept to the truck by any avoidance (m), over the re-checked trajectories.
  double least_clearance_m = 0.0;
  std::vector<VerifyFailure> failures;

  [[nodiscard]] bool ok() const noexcept { return failures.empty(); }
};

/// Re-checks the store. Throws UsageError when it is not a results store, InputError when a
/// stored maneuver or certificate cannot be read; a claim that does not hold is a failure in the
/// report, not an exception.
[[nodiscard]] VerifyReport verify_results(const std::filesystem::path& results_sqlite,
                                          const VerifyOptions& options = {});

/// The report as text (counts per region and evidence, then every failure) and as JSON.
[[nodiscard]] std::string to_text(const VerifyReport& report);
[[nodiscard]] nlohmann::ordered_json to_json(const VerifyReport& report);
/// Writes to_json(report) to DIR/verify.json (what `emrm reproduce` keeps and the report shows).
void write_verify_report(const std::filesystem::path& dir, const VerifyReport& report);

}  // namespace emrm::results
