#include "fit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <nlopt.hpp>
#include <set>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"

namespace emrm::calibration {
namespace {

using fit::Optimum;
using fit::Problem;

// χ²(1) at 95 %: the profile-likelihood interval is where n·ln(SSE_profile / SSE_min) stays below it.
constexpr double kChi2_95 = 3.841458820694124;
// |correlation| above this: two fitted parameters are not separately identifiable.
constexpr double kCorrelationLimit = 0.995;

// The parameters a calibration can fit: name, field and default search range, in one place.
struct Calibratable {
  std::string_view name;
  double sim::ActuationConfig::*field;
  FitBounds bounds;
};
constexpr std::array kCalibratable{
    Calibratable{"brake_dead_time_s", &sim::ActuationConfig::brake_dead_time_s, {0.0, 1.0}},
    Calibratable{"brake_ramp_s", &sim::ActuationConfig::brake_ramp_s, {0.0, 1.5}},
    Calibratable{"max_decel_mps2", &sim::ActuationConfig::max_decel_mps2, {2.0, 15.0}},
    Calibratable{"perception_latency_s", &sim::ActuationConfig::perception_latency_s, {0.0, 1.5}},
};

const Calibratable& calibratable(const std::string& name) {
  for (const auto& c : kCalibratable)
    if (c.name == name) return c;
  throw UsageError(fmt::format("--fit: '{}' cannot be calibrated; expected one of: {}", name,
                               core::join(calibratable_parameters(), ", ")));
}

double& parameter(sim::ActuationConfig& a, const std::string& name) { return a.*calibratable(name).field; }

// Every objective value computed, by point. In a problem of one coordinate each is a point of the
// profile already, so the interval's ends are bracketed by them before bisecting.
using Evaluations = std::map<std::vector<double>, double>;

// 95 % profile-likelihood interval of coordinate `i`: where n·ln(SSE_profile/SSE_min) ≤ χ²(1), or
// for a χ² objective where χ²_profile − χ²_min ≤ χ²(1).
std::pair<double, double> profile_interval(const Problem& p, const Optimum& at, std::size_t i,
                                           const Evaluations& seen) {
  const double n = static_cast<double>(p.observations);
  const double floor_sse = std::max(at.sse, 1e-18 * n);
  const auto excess_of = [&](double sse) {
    return (p.chi_square ? sse - at.sse : n * std::log(std::max(sse, floor_sse) / floor_sse)) - kChi2_95;
  };
  const auto excess = [&](double value) { return excess_of(fit::minimise(p, {{i, value}}, at.x, false).sse); };
  const auto side = [&](double bound) {
    double inside = at.x[i];
    double outside = bound;
    bool outside_known = false;
    if (p.low.size() == 1) {
      const auto distance = [&](double x) { return (x - at.x[i]) * (bound > at.x[i] ? 1.0 : -1.0); };
      for (const auto& [x, sse] : seen)
        if (distance(x[0]) > 0.0 && distance(x[0]) < distance(outside) && excess_of(sse) > 0.0) {
          outside = x[0];
          outside_known = true;
        }
      for (const auto& [x, sse] : seen)
        if (distance(x[0]) > distance(inside) && distance(x[0]) < distance(outside) && excess_of(sse) <= 0.0)
          inside = x[0];
    }
    if (!outside_known && excess(bound) <= 0.0) return bound;
    const double tolerance = p.interval_tolerance * (p.high[i] - p.low[i]);
    for (int k = 0; k < 40 && std::abs(outside - inside) > tolerance; ++k) {
      const double mid = 0.5 * (inside + outside);
      (excess(mid) <= 0.0 ? inside : outside) = mid;
    }
    return 0.5 * (inside + outside);
  };
  return {side(p.low[i]), side(p.high[i])};
}

// Correlations of the fitted coordinates from a finite-difference Hessian of the SSE (the
// Gauss–Newton covariance is proportional to its inverse).
std::vector<std::vector<double>> correlations(const Problem& p, const Optimum& at, std::size_t fitted) {
  const std::size_t n = p.low.size();
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i) h[i] = 1e-4 * std::max(1e-3, p.high[i] - p.low[i]);
  const auto f = [&](std::size_t i, double di, std::size_t j, double dj) {
    std::vector<double> x = at.x;
    x[i] += di;
    x[j] += dj;
    return p.sse(x);
  };
  // Row-major n×n matrices: the Hessian, and its inverse by Gauss–Jordan (small and symmetric); a
  // singular Hessian means perfectly correlated parameters.
  std::vector<double> hess(n * n), inv(n * n, 0.0);
  const auto at_ = [n](std::vector<double>& m, std::size_t r, std::size_t c) -> double& { return m[r * n + c]; };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i; j < n; ++j)
      at_(hess, i, j) = at_(hess, j, i) =
          (f(i, h[i], j, h[j]) - f(i, h[i], j, -h[j]) - f(i, -h[i], j, h[j]) + f(i, -h[i], j, -h[j])) /
          (4.0 * h[i] * h[j]);
  for (std::size_t i = 0; i < n; ++i) at_(inv, i, i) = 1.0;
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::abs(at_(hess, r, c)) > std::abs(at_(hess, pivot, c))) pivot = r;
    if (std::abs(at_(hess, pivot, c)) < 1e-300)
      return std::vector<std::vector<double>>(fitted, std::vector<double>(fitted, 1.0));
    for (std::size_t k = 0; k < n; ++k) {
      std::swap(at_(hess, c, k), at_(hess, pivot, k));
      std::swap(at_(inv, c, k), at_(inv, pivot, k));
    }
    const double d = at_(hess, c, c);
    for (std::size_t k = 0; k < n; ++k) {
      at_(hess, c, k) /= d;
      at_(inv, c, k) /= d;
    }
    for (std::size_t r = 0; r < n; ++r) {
      if (r == c) continue;
      const double m = at_(hess, r, c);
      for (std::size_t k = 0; k < n; ++k) {
        at_(hess, r, k) -= m * at_(hess, c, k);
        at_(inv, r, k) -= m * at_(inv, c, k);
      }
    }
  }
  std::vector<std::vector<double>> out(fitted, std::vector<double>(fitted));
  for (std::size_t i = 0; i < fitted; ++i)
    for (std::size_t j = 0; j < fitted; ++j)
      out[i][j] = at_(inv, i, j) / std::sqrt(std::abs(at_(inv, i, i) * at_(inv, j, j)));
  return out;
}

}  // namespace

namespace fit {

Optimum minimise(const Problem& p, const std::map<std::size_t, double>& fixed, const std::vector<double>& guess,
                 bool multistart) {
  std::vector<std::size_t> free;
  for (std::size_t i = 0; i < p.low.size(); ++i)
    if (!fixed.contains(i)) free.push_back(i);
  std::vector<double> full = guess;
  for (const auto& [i, v] : fixed) full[i] = v;
  Optimum best{full, p.sse(full), true};
  if (free.empty()) return best;
  const auto objective = [&](const std::vector<double>& x) {
    for (std::size_t k = 0; k < free.size(); ++k) full[free[k]] = x[k];
    return p.sse(full);
  };
  best.sse = INFINITY;
  best.converged = false;
  for (const double start : {-1.0, 0.25, 0.75}) {  // -1: the guess
    if (start >= 0.0 && (!multistart || p.piecewise_constant)) break;
    std::vector<double> x, lo, hi;
    for (const std::size_t i : free) {
      lo.push_back(p.low[i]);
      hi.push_back(p.high[i]);
      x.push_back(start < 0.0 ? std::clamp(guess[i], p.low[i], p.high[i]) : p.low[i] + start * (p.high[i] - p.low[i]));
    }
    // A count has no slope to follow: DIRECT-L divides the box and stops after its budget.
    nlopt::opt opt(p.piecewise_constant ? nlopt::GN_DIRECT_L : nlopt::LN_SBPLX, static_cast<unsigned>(free.size()));
    opt.set_lower_bounds(lo);
    opt.set_upper_bounds(hi);
    opt.set_min_objective([](const std::vector<double>& v, std::vector<double>& /*grad*/,
                             void* data) { return (*static_cast<decltype(&objective)>(data))(v); },
                          const_cast<void*>(static_cast<const void*>(&objective)));
    opt.set_xtol_abs(1e-9);
    opt.set_ftol_rel(1e-15);
    opt.set_maxeval(p.max_evaluations);
    double value = INFINITY;
    bool ok = false;
    try {
      const nlopt::result r = opt.optimize(x, value);
      ok = r > 0 && (p.piecewise_constant || r != nlopt::MAXEVAL_REACHED) && r != nlopt::MAXTIME_REACHED;
    } catch (const std::exception&) {
      ok = false;  // a roundoff-limited stop still leaves x at the best point found
      value = objective(x);
    }
    if (value < best.sse) {
      for (std::size_t k = 0; k < free.size(); ++k) full[free[k]] = x[k];
      best = {full, value, ok};
    }
  }
  return best;
}

CalibrationResult solve(const Problem& problem, const CalibrationRequest& request, bool check_correlations) {
  auto seen = std::make_shared<Evaluations>();
  Problem p = problem;
  p.sse = [f = problem.sse, seen](const std::vector<double>& x) {
    if (const auto it = seen->find(x); it != seen->end()) return it->second;
    return (*seen)[x] = f(x);
  };
  std::vector<double> guess;
  for (std::size_t i = 0; i < p.low.size(); ++i) guess.push_back(0.5 * (p.low[i] + p.high[i]));
  const Optimum best = minimise(p, {}, guess);
  CalibrationResult out;
  out.observations = p.observations;
  out.converged = best.converged && std::isfinite(best.sse);
  out.residual_rms = std::sqrt(best.sse / static_cast<double>(p.observations));
  out.actuation = request.start;
  const std::size_t k = request.fit.size();
  for (std::size_t i = 0; i < k; ++i) {
    const std::string& name = request.fit[i];
    FittedValue v;
    v.value = best.x[i];
    std::tie(v.ci_low, v.ci_high) = profile_interval(p, best, i, *seen);
    const double span = p.high[i] - p.low[i];
    const bool at_low = v.ci_low <= p.low[i] + 1e-9 * span;
    const bool at_high = v.ci_high >= p.high[i] - 1e-9 * span;
    v.identifiable = !(at_low && at_high);
    if (!v.identifiable)
      out.warnings.push_back(fmt::format(
          "{} is not identifiable from these data: its profile likelihood stays within the 95 % level over the whole "
          "search range [{}, {}]",
          name, p.low[i], p.high[i]));
    else if (v.value <= p.low[i] + 1e-6 * span || v.value >= p.high[i] - 1e-6 * span)
      out.warnings.push_back(fmt::format("{} = {} lies on its bound [{}, {}]: the bounds exclude the data's best fit",
                                         name, v.value, p.low[i], p.high[i]));
    out.fitted[name] = v;
    parameter(out.actuation, name) = v.value;
  }
  if (k > 1 && check_correlations) {
    const auto rho = correlations(p, best, k);
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t j = i + 1; j < k; ++j)
        if (!(std::abs(rho[i][j]) < kCorrelationLimit))
          out.warnings.push_back(fmt::format(
              "{} and {} are not separately identifiable from these data (correlation {:.3f}): only a combination "
              "of them is determined",
              request.fit[i], request.fit[j], rho[i][j]));
  }
  return out;
}

void add_fitted(Problem& p, const CalibrationRequest& request) {
  if (request.fit.empty()) throw UsageError("--fit: name at least one parameter");
  std::set<std::string> seen;
  for (const auto& name : request.fit) {
    (void)calibratable(name);
    if (!seen.insert(name).second) throw UsageError(fmt::format("--fit: '{}' is named twice", name));
    FitBounds b = default_bounds(name);
    if (const auto it = request.bounds.find(name); it != request.bounds.end()) b = it->second;
    if (!(std::isfinite(b.low) && std::isfinite(b.high) && b.low >= 0.0 && b.low < b.high))
      throw UsageError(fmt::format("--bounds: {} needs 0 <= LO < HI, got {}:{}", name, b.low, b.high));
    p.low.push_back(b.low);
    p.high.push_back(b.high);
  }
  for (const auto& [name, b] : request.bounds)
    if (!seen.contains(name)) throw UsageError(fmt::format("--bounds: '{}' is not among the --fit parameters", name));
}

sim::ActuationConfig with(const CalibrationRequest& request, const std::vector<double>& x) {
  sim::ActuationConfig a = request.start;
  for (std::size_t i = 0; i < request.fit.size(); ++i) parameter(a, request.fit[i]) = x[i];
  return a;
}

}  // namespace fit

std::vector<std::string> calibratable_parameters() {
  std::vector<std::string> names;
  for (const auto& c : kCalibratable) names.emplace_back(c.name);
  return names;
}

FitBounds default_bounds(const std::string& name) { return calibratable(name).bounds; }

}  // namespace emrm::calibration
