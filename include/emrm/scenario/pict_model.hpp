#pragma once

// PICT-style model files for `emrm ca` (docs/covering-arrays.md):
//
//   # comment
//   Speed: 30, 50, 70
//   Road:  dry, wet, icy
//   IF [Road] = "icy" THEN [Speed] <= 50;
//   [Speed] <> 70 OR NOT [Road] IN {"wet", "icy"};
//
// Constraints: IF p THEN q [ELSE r]; or a bare predicate p; predicates combine relations with
// AND, OR, NOT and parentheses; relations are [P] op literal|[Q] with op in = <> < <= > >=
// (ordering needs numbers), and [P] IN {v, ...}.

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/scenario/covering_array.hpp"

namespace emrm::scenario {

struct PictParameter {
  std::string name;
  std::vector<std::string> values;  ///< as written; numeric when they parse as numbers
  SourceLocation where;
};

/// A parsed model: parameters and compiled constraints. Copyable and immutable; violates() is
/// thread-safe.
class PictModel {
 public:
  struct Constraint;  // opaque: a compiled predicate tree

  PictModel(std::vector<PictParameter> parameters, std::vector<std::shared_ptr<const Constraint>> constraints);

  [[nodiscard]] const std::vector<PictParameter>& parameters() const noexcept { return parameters_; }
  [[nodiscard]] std::size_t constraint_count() const noexcept { return constraints_.size(); }
  /// Number of values of each parameter, in order.
  [[nodiscard]] std::vector<int> levels() const;
  /// True when the assigned entries of `row` (value indices, kDontCare for unassigned) already break
  /// a constraint: a constraint counts as broken only when its outcome no longer depends on the
  /// unassigned parameters. Fits RowViolates.
  [[nodiscard]] bool violates(std::span<const int> row) const;
  /// A RowViolates bound to this model (empty when there are no constraints). Borrows *this.
  [[nodiscard]] RowViolates row_violates() const;

 private:
  std::vector<PictParameter> parameters_;
  std::vector<std::shared_ptr<const Constraint>> constraints_;
};

/// Parses model text; `file` names it in errors. Throws InputError at file:line:column for: no
/// parameters, a parameter without values, a duplicate parameter or value, a constraint naming an
/// unknown parameter, syntax PICT has but emrm does not (sub-models, LIKE, ...) or that is
/// malformed, ordering comparisons with non-numbers, and a constraint set no row satisfies
/// (pointing at the first constraint that makes it unsatisfiable). Deciding that takes at most
/// `max_search_steps` steps of the constraint search (SearchBudget, for the whole set and the search
/// for the culprit together); more is an InputError at the first constraint naming the limit.
[[nodiscard]] PictModel parse_pict_model(std::string_view text, const std::string& file,
                                         std::uint64_t max_search_steps = kDefaultMaxSearchSteps);

/// Reads and parses a model file. Throws InputError as parse_pict_model, or when unreadable.
[[nodiscard]] PictModel load_pict_model(const std::filesystem::path& path,
                                        std::uint64_t max_search_steps = kDefaultMaxSearchSteps);

}  // namespace emrm::scenario
