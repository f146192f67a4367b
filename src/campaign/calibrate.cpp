#include "emrm/campaign/calibrate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <nlopt.hpp>
#include <set>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"

namespace emrm::campaign {
namespace {

// χ²(1) at 95 %: the profile-likelihood interval is where n·ln(SSE_profile / SSE_min) stays below it.
constexpr double kChi2_95 = 3.841458820694124;
// |correlation| above this: two fitted parameters are not separately identifiable.
constexpr double kCorrelationLimit = 0.995;

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

struct Column {
  std::string name;
  bool required = true;
};

// The columns' positions in a header row; InputError at the header for a missing one.
std::map<std::string, std::size_t> find_columns(const core::CsvRecord& header, const std::vector<Column>& columns,
                                                const std::string& file) {
  std::map<std::string, std::size_t> at;
  for (std::size_t i = 0; i < header.fields.size(); ++i) at[trim(header.fields[i])] = i;
  std::map<std::string, std::size_t> out;
  std::vector<std::string> expected;
  for (const auto& c : columns) expected.push_back(c.name);
  for (const auto& c : columns) {
    if (const auto it = at.find(c.name); it != at.end()) out[c.name] = it->second;
    else if (c.required)
      throw InputError({file, header.lines.front(), 1},
                       fmt::format("missing column '{}'; expected the columns {}", c.name, core::join(expected, ", ")));
  }
  return out;
}

// A finite number from a field, or InputError at the field.
double number_at(const core::CsvRecord& r, std::size_t i, const std::string& column, const std::string& file) {
  if (i >= r.fields.size())
    throw InputError({file, r.lines.front(), r.columns.back()}, fmt::format("row has no '{}' field", column));
  const std::string text = trim(r.fields[i]);
  const std::optional<double> v = core::parse_finite_number(text);
  if (!v)
    throw InputError({file, r.lines[i], r.columns[i]},
                     fmt::format("{}: expected a finite number, got '{}'", column, text));
  return *v;
}

void require(bool ok, const core::CsvRecord& r, std::size_t i, const std::string& file, const std::string& what) {
  if (!ok) throw InputError({file, r.lines[i], r.columns[i]}, what);
}

std::vector<core::CsvRecord> records_of(const std::filesystem::path& file) {
  auto records = core::parse_csv(core::read_input_file(file), file.string());
  if (records.size() < 2) throw InputError({file.string(), 1, 1}, "expected a header row and at least one data row");
  return records;
}

// The parameters a brake test can identify: name, field and default search range, in one place.
struct Calibratable {
  std::string_view name;
  double sim::ActuationConfig::*field;
  FitBounds bounds;
};
constexpr std::array kCalibratable{
    Calibratable{"brake_dead_time_s", &sim::ActuationConfig::brake_dead_time_s, {0.0, 1.0}},
    Calibratable{"brake_ramp_s", &sim::ActuationConfig::brake_ramp_s, {0.0, 1.5}},
    Calibratable{"max_decel_mps2", &sim::ActuationConfig::max_decel_mps2, {2.0, 15.0}},
};

const Calibratable& calibratable(const std::string& name) {
  for (const auto& c : kCalibratable)
    if (c.name == name) return c;
  throw UsageError(fmt::format("--fit: '{}' cannot be calibrated from brake tests; expected one of: {}", name,
                               core::join(calibratable_parameters(), ", ")));
}

double& parameter(sim::ActuationConfig& a, const std::string& name) { return a.*calibratable(name).field; }

// A least-squares problem over the fitted parameters (then any nuisance parameters).
struct Problem {
  std::vector<double> low, high;
  std::function<double(const std::vector<double>&)> sse;
  std::size_t observations = 0;
};

struct Optimum {
  std::vector<double> x;
  double sse = 0.0;
  bool converged = false;
};

// Minimises over the free coordinates (those not in `fixed`) from `guess`, and with `multistart` also
// from two more points of the box.
Optimum minimise(const Problem& p, const std::map<std::size_t, double>& fixed, const std::vector<double>& guess,
                 bool multistart = true) {
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
    if (start >= 0.0 && !multistart) break;
    std::vector<double> x, lo, hi;
    for (const std::size_t i : free) {
      lo.push_back(p.low[i]);
      hi.push_back(p.high[i]);
      x.push_back(start < 0.0 ? std::clamp(guess[i], p.low[i], p.high[i]) : p.low[i] + start * (p.high[i] - p.low[i]));
    }
    nlopt::opt opt(nlopt::LN_SBPLX, static_cast<unsigned>(free.size()));
    opt.set_lower_bounds(lo);
    opt.set_upper_bounds(hi);
    opt.set_min_objective(
        [](const std::vector<double>& v, std::vector<double>& /*grad*/, void* data) {
          return (*static_cast<decltype(&objective)>(data))(v);
        },
        const_cast<void*>(static_cast<const void*>(&objective)));
    opt.set_xtol_abs(1e-9);
    opt.set_ftol_rel(1e-15);
    opt.set_maxeval(40000);
    double value = INFINITY;
    bool ok = false;
    try {
      const nlopt::result r = opt.optimize(x, value);
      ok = r > 0 && r != nlopt::MAXEVAL_REACHED && r != nlopt::MAXTIME_REACHED;
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

// 95 % profile-likelihood interval of coordinate `i`: where n·ln(SSE_profile/SSE_min) ≤ χ²(1).
std::pair<double, double> profile_interval(const Problem& p, const Optimum& at, std::size_t i) {
  const double n = static_cast<double>(p.observations);
  const double floor_sse = std::max(at.sse, 1e-18 * n);
  const auto excess = [&](double value) {
    const Optimum o = minimise(p, {{i, value}}, at.x, false);
    return n * std::log(std::max(o.sse, floor_sse) / floor_sse) - kChi2_95;
  };
  const auto side = [&](double bound) {
    if (excess(bound) <= 0.0) return bound;
    double inside = at.x[i];
    double outside = bound;
    const double tolerance = 1e-4 * (p.high[i] - p.low[i]);
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

CalibrationResult solve(const Problem& p, const CalibrationRequest& request) {
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
    std::tie(v.ci_low, v.ci_high) = profile_interval(p, best, i);
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
  if (k > 1) {
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

// The fitted parameters' bounds, checked.
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

}  // namespace

std::vector<std::string> calibratable_parameters() {
  std::vector<std::string> names;
  for (const auto& c : kCalibratable) names.emplace_back(c.name);
  return names;
}

FitBounds default_bounds(const std::string& name) { return calibratable(name).bounds; }

std::vector<StopRecord> read_stops(const std::filesystem::path& file) {
  const auto records = records_of(file);
  const std::string f = file.string();
  const auto col = find_columns(records.front(),
                                {{"speed_kph"}, {"mu"}, {"stop_distance_m"}, {"time_to_stop_s", false}}, f);
  std::vector<StopRecord> out;
  for (std::size_t k = 1; k < records.size(); ++k) {
    const auto& r = records[k];
    StopRecord s;
    s.speed_kph = number_at(r, col.at("speed_kph"), "speed_kph", f);
    require(s.speed_kph > 0.0, r, col.at("speed_kph"), f, fmt::format("speed_kph: expected a value > 0, got {}", s.speed_kph));
    s.mu = number_at(r, col.at("mu"), "mu", f);
    require(s.mu > 0.0 && s.mu <= 2.0, r, col.at("mu"), f, fmt::format("mu: expected 0 < mu <= 2, got {}", s.mu));
    s.stop_distance_m = number_at(r, col.at("stop_distance_m"), "stop_distance_m", f);
    require(s.stop_distance_m > 0.0, r, col.at("stop_distance_m"), f,
            fmt::format("stop_distance_m: expected a distance > 0, got {}", s.stop_distance_m));
    if (const auto it = col.find("time_to_stop_s"); it != col.end()) {
      s.time_to_stop_s = number_at(r, it->second, "time_to_stop_s", f);
      require(s.time_to_stop_s > 0.0, r, it->second, f,
              fmt::format("time_to_stop_s: expected a time > 0, got {}", s.time_to_stop_s));
    }
    out.push_back(s);
  }
  return out;
}

std::vector<TraceSample> read_decel_trace(const std::filesystem::path& file) {
  const auto records = records_of(file);
  const std::string f = file.string();
  const auto col = find_columns(records.front(), {{"run"}, {"t_s"}, {"speed_mps"}}, f);
  std::vector<TraceSample> out;
  std::map<std::string, double> last_t;
  for (std::size_t k = 1; k < records.size(); ++k) {
    const auto& r = records[k];
    require(col.at("run") < r.fields.size(), r, r.fields.size() - 1, f, "row has no 'run' field");
    TraceSample s;
    s.run = trim(r.fields[col.at("run")]);
    s.t_s = number_at(r, col.at("t_s"), "t_s", f);
    s.speed_mps = number_at(r, col.at("speed_mps"), "speed_mps", f);
    require(s.speed_mps >= 0.0, r, col.at("speed_mps"), f, fmt::format("speed_mps: expected a speed >= 0, got {}", s.speed_mps));
    if (const auto it = last_t.find(s.run); it != last_t.end())
      require(s.t_s > it->second, r, col.at("t_s"), f,
              fmt::format("t_s: expected the times of run '{}' to increase, got {} after {}", s.run, s.t_s, it->second));
    last_t[s.run] = s.t_s;
    out.push_back(s);
  }
  return out;
}

double braked_speed_mps(const sim::ActuationConfig& a, double mu, double v0, double t_s) {
  const double decel = a.full_decel_mps2(mu);
  const double s = t_s - a.brake_dead_time_s;
  if (s <= 0.0) return v0;
  const double tr = a.brake_ramp_s;
  const double v = tr > 0.0 && s <= tr ? v0 - decel * s * s / (2.0 * tr) : v0 - decel * (0.5 * tr + (s - tr));
  return std::max(0.0, v);
}

CalibrationResult calibrate_stops(const std::vector<StopRecord>& stops, const CalibrationRequest& request) {
  Problem p;
  add_fitted(p, request);
  p.observations = 0;
  for (const auto& s : stops) p.observations += s.time_to_stop_s > 0.0 ? 2 : 1;
  p.sse = [&stops, &request](const std::vector<double>& x) {
    const sim::ActuationConfig a = with(request, x);
    double sum = 0.0;
    for (const auto& s : stops) {
      const double v = s.speed_kph / 3.6;
      const double d = a.stopping_distance_m(v, s.mu, false) - s.stop_distance_m;
      sum += d * d;
      if (s.time_to_stop_s > 0.0) {
        const double t = (a.stopping_time_s(v, s.mu, false) - s.time_to_stop_s) * v;  // in metres, like d
        sum += t * t;
      }
    }
    return sum;
  };
  return solve(p, request);
}

CalibrationResult calibrate_trace(const std::vector<TraceSample>& trace, const CalibrationRequest& request) {
  Problem p;
  add_fitted(p, request);
  // Each run's initial speed is a nuisance parameter within 2 m/s of its first sample.
  std::vector<std::string> runs;
  std::map<std::string, std::size_t> run_index;
  for (const auto& s : trace)
    if (!run_index.contains(s.run)) {
      run_index[s.run] = runs.size();
      runs.push_back(s.run);
      p.low.push_back(std::max(0.0, s.speed_mps - 2.0));
      p.high.push_back(s.speed_mps + 2.0);
    }
  const std::size_t fitted = request.fit.size();
  p.observations = trace.size();
  std::vector<std::size_t> index_of;
  for (const auto& s : trace) index_of.push_back(fitted + run_index.at(s.run));
  p.sse = [&trace, &request, index_of](const std::vector<double>& x) {
    const sim::ActuationConfig a = with(request, x);
    double sum = 0.0;
    for (std::size_t k = 0; k < trace.size(); ++k) {
      const double d = braked_speed_mps(a, 1.0, x[index_of[k]], trace[k].t_s) - trace[k].speed_mps;
      sum += d * d;
    }
    return sum;
  };
  return solve(p, request);
}

std::string profile_yaml(const CalibrationResult& result, const std::string& command) {
  const sim::ActuationConfig& a = result.actuation;
  std::string fitted;
  for (const auto& [name, v] : result.fitted)
    fitted += fmt::format("#   {} = {:.4g}  (95 % interval {:.4g} to {:.4g}{})\n", name, v.value, v.ci_low, v.ci_high,
                          v.identifiable ? "" : ", NOT IDENTIFIABLE");
  std::string warnings;
  for (const auto& w : result.warnings) warnings += "# warning: " + w + "\n";
  return fmt::format(
      "# Made by: {}\n# Fitted (residual RMS {:.4g} over {} observations):\n{}{}"
      "description: calibrated actuation\n"
      "actuation:\n"
      "  perception_latency_s: {}\n  brake_dead_time_s: {}\n  brake_ramp_s: {}\n  max_decel_mps2: {}\n"
      "  steer_dead_time_s: {}\n  steer_time_constant_s: {}\n",
      command, result.residual_rms, result.observations, fitted, warnings, a.perception_latency_s,
      a.brake_dead_time_s, a.brake_ramp_s, a.max_decel_mps2, a.steer_dead_time_s, a.steer_time_constant_s);
}

}  // namespace emrm::campaign
