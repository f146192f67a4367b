#pragma once

// The least-squares machinery of `emrm calibrate` (internal to src/campaign): the calibratable
// parameters, NLopt minimisation, 95 % profile-likelihood intervals and the identifiability
// warnings (docs/actuation.md, "Calibration").

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "emrm/calibration/calibrate.hpp"

namespace emrm::calibration::fit {

/// A least-squares problem over the fitted parameters (then any nuisance parameters).
struct Problem {
  std::vector<double> low, high;
  std::function<double(const std::vector<double>&)> sse;
  std::size_t observations = 0;
  /// `sse` is a χ² (residuals divided by known standard deviations): the interval is where it rises
  /// by χ²(1, 95 %). Otherwise the variance is estimated from the residuals (n·ln(SSE/SSE_min)).
  bool chi_square = false;
  /// `sse` is piecewise constant (it counts cells): a global search (NLopt's DIRECT-L) with at most
  /// `max_evaluations`, instead of local searches from three starts.
  bool piecewise_constant = false;
  int max_evaluations = 40000;
  /// The interval's ends are found to this fraction of the search range.
  double interval_tolerance = 1e-4;
};

struct Optimum {
  std::vector<double> x;
  double sse = 0.0;
  bool converged = false;
};

/// Minimises over the coordinates not in `fixed`, from `guess` (and, unless `multistart` is false
/// or the problem is piecewise constant, from two more points of the box).
[[nodiscard]] Optimum minimise(const Problem& p, const std::map<std::size_t, double>& fixed,
                               const std::vector<double>& guess, bool multistart = true);

/// The fitted values, their intervals and warnings: not identifiable, on a bound, and (with
/// `check_correlations`, for smooth problems) pairs of parameters only a combination of which is
/// determined.
[[nodiscard]] CalibrationResult solve(const Problem& p, const CalibrationRequest& request,
                                      bool check_correlations = true);

/// The fitted parameters' search ranges appended to `p` (the request's bounds over the defaults).
/// Throws UsageError for an unknown or repeated name, or bounds that are empty or negative.
void add_fitted(Problem& p, const CalibrationRequest& request);

/// The request's starting actuation with the fitted coordinates of `x` set.
[[nodiscard]] sim::ActuationConfig with(const CalibrationRequest& request, const std::vector<double>& x);

}  // namespace emrm::calibration::fit
