#pragma once

// Covering arrays of strength 2 and 3 over mixed-level factors, with constraints and forced seed
// rows. Every t-tuple of values that some valid row can contain appears in at least one row.
// A greedy construction, one row at a time in the AETG/PICT family, is followed by a tabu search
// that removes rows while coverage can be repaired (docs/covering-arrays.md).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace emrm::scenario {

/// Marks an entry of a partial row (a seed row, or a row under construction) as unassigned.
inline constexpr int kDontCare = -1;

/// Says whether a row breaks a constraint. It receives rows whose entries are level indices or
/// kDontCare. On a complete row, true means the row is invalid. On a partial row it may answer true
/// only when every completion is invalid (typically: a constraint whose factors are all assigned
/// fails); answering false for partial rows is always allowed, only slower. An empty function means
/// "no constraints".
using RowViolates = std::function<bool(std::span<const int> row)>;

/// Default work budget of the search that completes rows under constraints (SearchBudget), for each
/// operation: 10 million steps. A step costs from about 20 ns (two short constraints) to 1 us (a
/// hundred), so a hopeless search stops after a fraction of a second to about 10 s; a model of 75
/// factors and 20 constraints needs under half of it at t = 2 (docs/covering-arrays.md, "Limits").
inline constexpr std::uint64_t kDefaultMaxSearchSteps = 10'000'000;

/// The work budget of the depth-first search behind complete_row, shared by every search of one
/// operation (loading a model, generating an array, checking one). That search is exponential in
/// the worst case, and a model can be small and still never finish. One step is one node of the
/// search, which is one call of the RowViolates on a (partial) row. Spending past the limit throws
/// emrm::UsageError naming the limit and `ca --max-search-steps`. Steps are counted, never time,
/// so a run that stays within its budget gives the same result as one without a budget.
class SearchBudget {
 public:
  explicit SearchBudget(std::uint64_t max_steps = kDefaultMaxSearchSteps) noexcept : limit_(max_steps) {}

  /// Takes one step; throws UsageError when that is more than the limit.
  void spend();
  [[nodiscard]] std::uint64_t used() const noexcept { return used_; }
  [[nodiscard]] std::uint64_t limit() const noexcept { return limit_; }

 private:
  std::uint64_t limit_;
  std::uint64_t used_ = 0;
};

struct CoveringArrayOptions {
  int strength = 2;             ///< t, 2 or 3
  std::uint64_t seed = 1;       ///< same seed, same array
  int candidates_per_row = 24;  ///< candidate rows built per emitted row
  int restarts = 2;             ///< whole-array greedy attempts; the smallest is kept
  /// Most t-tuples (summed over every t-subset of the factors) the generator takes on: its tables
  /// grow with them. More is refused with emrm::UsageError naming the limit.
  std::size_t max_tuples = 20'000'000;
  /// Work budget of the constraint search (SearchBudget), shared by the whole generation: finding
  /// the tuples no valid row contains, completing seed rows, and keeping candidate rows completable.
  std::uint64_t max_search_steps = kDefaultMaxSearchSteps;
  bool remove_redundant_rows = true;  ///< drop rows whose every tuple is covered elsewhere
  /// Effort of the post-optimisation that removes rows from the greedy array (a tabu search, see
  /// docs/covering-arrays.md): it gives up on a size after this many moves per required t-tuple
  /// without a new lowest count of uncovered tuples, and returns the last complete array. 0 keeps
  /// the greedy array. Effort counts moves, not time, so results do not depend on the machine.
  double improvement_effort = 10.0;
  /// Cap on the post-optimisation's moves in all, whatever the effort. A move costs about 1-5 us
  /// in a Release build, more with more rows and more t-subsets through a column.
  std::int64_t improvement_max_moves = 500'000;
  std::vector<std::vector<int>> seed_rows;  ///< forced first rows; kDontCare entries are filled
};

struct CoveringArray {
  std::vector<int> levels;
  int strength = 2;
  std::vector<std::vector<int>> rows;  ///< complete rows of level indices, seed rows first
  std::size_t required_tuples = 0;     ///< t-tuples that some valid row contains (all covered)
  std::size_t forbidden_tuples = 0;    ///< t-tuples no valid row contains (not required)
};

/// Builds a covering array of `options.strength` over factors with `levels[i]` values each.
/// Deterministic for equal inputs, options and seed. Throws std::invalid_argument when strength is
/// not 2 or 3, exceeds levels.size(), a level count is < 1, UsageError when the t-tuples exceed
/// max_tuples, a seed row has the wrong length or an
/// out-of-range entry, candidates_per_row or restarts are non-positive, or improvement_effort is
/// outside [0, 1e6] or improvement_max_moves negative; throws std::domain_error when no valid row
/// exists or a seed row cannot be completed without breaking a constraint, and UsageError when the
/// constraint search takes more than max_search_steps.
[[nodiscard]] CoveringArray generate_covering_array(const std::vector<int>& levels, const CoveringArrayOptions& options,
                                                    const RowViolates& violates = {});

/// A complete row extending `partial` (kDontCare entries filled) that breaks no constraint, or
/// nothing when there is none. Depth-first search, exponential in the worst case; it spends one
/// step of `budget` per node and throws UsageError when the budget runs out.
[[nodiscard]] std::optional<std::vector<int>> complete_row(const std::vector<int>& levels, std::vector<int> partial,
                                                           const RowViolates& violates, SearchBudget& budget);

/// As above, with a budget of its own of kDefaultMaxSearchSteps.
[[nodiscard]] std::optional<std::vector<int>> complete_row(const std::vector<int>& levels, std::vector<int> partial,
                                                           const RowViolates& violates);

struct ArrayCheck {
  std::size_t required_tuples = 0;
  std::size_t covered_tuples = 0;
  std::size_t invalid_rows = 0;  ///< rows that break a constraint or have out-of-range entries
  std::string first_problem;     ///< empty when ok()
  [[nodiscard]] bool ok() const { return covered_tuples == required_tuples && invalid_rows == 0; }
};

/// Checks `rows` by brute force, sharing no code with the generator's bookkeeping: every t-tuple a
/// valid row can contain must appear in some row, and no row may break a constraint. Deciding
/// whether an uncovered tuple is feasible shares one SearchBudget of `max_search_steps`; throws
/// UsageError when it runs out.
[[nodiscard]] ArrayCheck check_covering_array(const std::vector<int>& levels, int strength,
                                              const std::vector<std::vector<int>>& rows,
                                              const RowViolates& violates = {},
                                              std::uint64_t max_search_steps = kDefaultMaxSearchSteps);

}  // namespace emrm::scenario
