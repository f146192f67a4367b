#include "emrm/scenario/statistics.hpp"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace emrm::scenario {
namespace {

void require(bool condition, const char* what) {
  if (!condition) throw std::invalid_argument(what);
}

bool is_confidence(double confidence) { return confidence > 0.0 && confidence < 1.0; }

// ⌈x⌉ that forgives the last bits of rounding: a size that is mathematically an integer must not
// come out one too large because, say, 2·0.1² is 0.020000000000000004.
std::size_t ceil_count(double x) {
  const double rounded = std::round(x);
  const double n = std::abs(x - rounded) <= 1e-12 * std::max(1.0, std::abs(x)) ? rounded : std::ceil(x);
  return static_cast<std::size_t>(std::max(0.0, n));
}

}  // namespace

double normal_quantile(double confidence) {
  require(is_confidence(confidence), "normal_quantile: confidence must be in (0, 1)");
  const boost::math::normal_distribution<double> standard;
  return boost::math::quantile(standard, 1.0 - 0.5 * (1.0 - confidence));
}

Interval wilson_interval(double successes, double n, double confidence) {
  require(is_confidence(confidence), "wilson_interval: confidence must be in (0, 1)");
  require(std::isfinite(n) && n >= 0.0, "wilson_interval: n must be finite and >= 0");
  require(std::isfinite(successes) && successes >= 0.0, "wilson_interval: successes must be finite and >= 0");
  require(successes <= n, "wilson_interval: successes must not exceed n");
  if (n == 0.0) return {};

  const double z = normal_quantile(confidence);
  const double z2 = z * z;
  const double p = successes / n;
  const double denominator = 1.0 + z2 / n;
  const double centre = (p + z2 / (2.0 * n)) / denominator;
  const double half = z / denominator * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  Interval interval{std::max(0.0, centre - half), std::min(1.0, centre + half)};
  // At p̂ = 0 (or 1) the bound is exactly 0 (or 1); the formula reaches it only up to rounding.
  if (successes == 0.0) interval.low = 0.0;
  if (successes == n) interval.high = 1.0;
  return interval;
}

double wilson_worst_half_width(double n, double confidence) {
  require(std::isfinite(n) && n >= 0.0, "wilson_worst_half_width: n must be finite and >= 0");
  const double z = normal_quantile(confidence);
  if (n == 0.0) return 0.5;  // the interval is [0, 1]
  return z / (2.0 * std::sqrt(n + z * z));
}

std::size_t wilson_sample_size(double epsilon, double confidence) {
  require(epsilon > 0.0 && epsilon < 0.5, "wilson_sample_size: epsilon must be in (0, 0.5)");
  const double z = normal_quantile(confidence);
  const double z2 = z * z;
  std::size_t n = std::max<std::size_t>(1, ceil_count(z2 / (4.0 * epsilon * epsilon) - z2));
  // The closed form can be one off at the rounding edge; settle it against the definition.
  while (wilson_worst_half_width(static_cast<double>(n), confidence) > epsilon) ++n;
  while (n > 1 && wilson_worst_half_width(static_cast<double>(n - 1), confidence) <= epsilon) --n;
  return n;
}

double hoeffding_probability(double n, double epsilon) {
  require(n >= 0.0, "hoeffding_probability: n must be >= 0");
  require(epsilon >= 0.0, "hoeffding_probability: epsilon must be >= 0");
  return std::min(1.0, 2.0 * std::exp(-2.0 * n * epsilon * epsilon));
}

double hoeffding_epsilon(double n, double delta) {
  require(n >= 0.0, "hoeffding_epsilon: n must be >= 0");
  require(delta > 0.0 && delta < 1.0, "hoeffding_epsilon: delta must be in (0, 1)");
  if (n == 0.0) return std::numeric_limits<double>::infinity();
  return std::sqrt(std::log(2.0 / delta) / (2.0 * n));
}

std::size_t hoeffding_sample_size(double epsilon, double delta) {
  require(epsilon > 0.0 && std::isfinite(epsilon), "hoeffding_sample_size: epsilon must be > 0");
  require(delta > 0.0 && delta < 1.0, "hoeffding_sample_size: delta must be in (0, 1)");
  return ceil_count(std::log(2.0 / delta) / (2.0 * epsilon * epsilon));
}

double effective_sample_size(std::span<const double> weights) {
  double sum = 0.0;
  double sum_of_squares = 0.0;
  for (const double w : weights) {
    sum += w;
    sum_of_squares += w * w;
  }
  return sum_of_squares > 0.0 ? sum * sum / sum_of_squares : 0.0;
}

WeightedEstimate weighted_success(std::span<const double> weights, std::span<const int> outcomes, double confidence) {
  require(weights.size() == outcomes.size(), "weighted_success: weights and outcomes differ in length");
  require(is_confidence(confidence), "weighted_success: confidence must be in (0, 1)");
  WeightedEstimate result;
  double weighted_successes = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    require(std::isfinite(weights[i]) && weights[i] >= 0.0, "weighted_success: weights must be finite and >= 0");
    require(outcomes[i] == 0 || outcomes[i] == 1, "weighted_success: outcomes must be 0 or 1");
    result.weight += weights[i];
    weighted_successes += weights[i] * outcomes[i];
  }
  result.n = weights.size();
  result.estimate = result.weight > 0.0 ? weighted_successes / result.weight : std::numeric_limits<double>::quiet_NaN();
  result.n_eff = effective_sample_size(weights);
  if (result.n_eff > 0.0) {
    // n_eff·Ŝ can overshoot n_eff in the last bit when every test succeeded.
    const double successes = std::clamp(result.n_eff * result.estimate, 0.0, result.n_eff);
    result.wilson = wilson_interval(successes, result.n_eff, confidence);
  }
  return result;
}

}  // namespace emrm::scenario
