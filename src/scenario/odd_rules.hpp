#pragma once

// The rules of a well-formed ODD, one part at a time, for validate(const Odd&) and for the ODD
// loader, which checks each part as soon as it is read (so that later defaults are derived from
// valid data) at the path of the part in the file. Each check fails at the Validator's current
// path (or a field below it) by throwing core::ConfigError.

#include <cstddef>
#include <string>
#include <vector>

#include "emrm/core/config.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/plan.hpp"

namespace emrm::scenario::detail {

/// Name, bins and kinks, or classes and their values. At the factor's path.
void check_factor_domain(core::Validator& v, const OddFactor& f);
/// One probability >= 0 per level, summing to 1. At the factor's path; needs a valid domain.
void check_factor_prior(core::Validator& v, const OddFactor& f);
/// A nominal value inside the domain (a whole number for an integer factor, a class's number for
/// a categorical one). At the factor's path; needs a valid domain.
void check_factor_nominal(core::Validator& v, const OddFactor& f);
/// The name of factor `i` is not that of an earlier factor. At the factor's path.
void check_factor_unique(core::Validator& v, const Odd& odd, std::size_t i);
/// At least one factor, at "factors".
void check_factor_count(core::Validator& v, const Odd& odd);
/// Strength, n_c, n_m, epsilon, delta and budget, at "coverage".
void check_coverage(core::Validator& v, const Odd& odd);
/// "budget must be >= 1, got N": also for a negative budget in a file, which no size_t holds.
[[nodiscard]] std::string budget_message(long long budget);
/// Malfunction mode `k` has an id no earlier mode has, and a region compiled over the factors. At
/// the mode's path.
void check_malfunction(core::Validator& v, const Odd& odd, std::size_t k);
/// At most 200 000 cells, at "factors".
void check_domain_size(core::Validator& v, const Odd& odd);
/// Some cell is relevant; else the culprit: the relevance predicate ("relevance") or the first
/// constraint that leaves no relevant cell ("constraints[i]"). Computes the relevant cells.
void check_satisfiable(core::Validator& v, const Odd& odd);

/// Every rule but check_satisfiable, in validate()'s order.
void check_odd(core::Validator& v, const Odd& odd);
/// validate(odd) for callers that need the relevant cells anyway (build_plan, measure_coverage):
/// every rule but satisfiability, then relevant_cells(odd), returned when there is one; else the
/// satisfiability rule names the culprit.
[[nodiscard]] std::vector<RelevantCell> validated_relevant_cells(const Odd& odd);

}  // namespace emrm::scenario::detail
