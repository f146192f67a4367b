#pragma once

// Binomial statistics of a scenario set (paper §V-B "Risk-weighted performance estimation"):
// Wilson score intervals, Hoeffding bounds, the per-cell sample size of Proposition
// "Per-cell sample size", and the weighted success estimator Ŝ(A).

#include <cstddef>
#include <span>

namespace emrm::scenario {

struct Interval {
  double low = 0.0;
  double high = 1.0;
  [[nodiscard]] double half_width() const noexcept { return 0.5 * (high - low); }
};

/// Two-sided standard-normal quantile z_{1−(1−confidence)/2} (Boost.Math), e.g. 1.959964 at 0.95.
/// Throws std::invalid_argument unless 0 < confidence < 1.
[[nodiscard]] double normal_quantile(double confidence);

/// Wilson score interval for `successes` of `n` at `confidence`; n = 0 gives [0, 1].
/// Throws std::invalid_argument when successes > n or confidence is not in (0, 1).
/// Example: 8 of 10 at 0.95 → [0.490, 0.943].
[[nodiscard]] Interval wilson_interval(double successes, double n, double confidence = 0.95);

/// Largest Wilson half-width over every possible outcome of n trials (at p̂ = ½):
/// z / (2·√(n + z²)).
[[nodiscard]] double wilson_worst_half_width(double n, double confidence = 0.95);

/// Smallest n whose worst-case Wilson half-width is ≤ epsilon: ⌈z²/(4ε²) − z²⌉, at least 1.
/// Throws std::invalid_argument unless 0 < epsilon < 0.5.
[[nodiscard]] std::size_t wilson_sample_size(double epsilon, double confidence = 0.95);

/// Hoeffding: P(|Ŝ − S| ≥ ε) ≤ 2·exp(−2·n·ε²) (capped at 1).
[[nodiscard]] double hoeffding_probability(double n, double epsilon);
/// The ε that Hoeffding guarantees with probability 1 − delta after n trials: √(ln(2/δ)/(2n)).
[[nodiscard]] double hoeffding_epsilon(double n, double delta);
/// Per-cell sample size n_c = ⌈ln(2/δ)/(2ε²)⌉ (Proposition "Per-cell sample size").
/// Throws std::invalid_argument unless epsilon > 0 and 0 < delta < 1.
[[nodiscard]] std::size_t hoeffding_sample_size(double epsilon, double delta);

/// Kish's effective sample size (Σw)²/Σw² of a set of weights; 0 for an empty set.
[[nodiscard]] double effective_sample_size(std::span<const double> weights);

struct WeightedEstimate {
  double estimate = 0.0;  ///< Ŝ(A) = Σ w·Y / Σ w (NaN when A holds no test)
  double weight = 0.0;    ///< Σ w
  std::size_t n = 0;      ///< tests in A
  double n_eff = 0.0;     ///< effective sample size of the weights
  Interval wilson;        ///< Wilson interval at n_eff with n_eff·Ŝ successes
};

/// Ŝ(A) over the tests given (those in A): weights w_i ≥ 0 and outcomes Y_i ∈ {0, 1}.
/// Throws std::invalid_argument when the spans differ in length or a weight is negative or not finite.
[[nodiscard]] WeightedEstimate weighted_success(std::span<const double> weights, std::span<const int> outcomes,
                                                double confidence = 0.95);

}  // namespace emrm::scenario
