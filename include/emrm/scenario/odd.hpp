#pragma once

// The operational design domain as data (paper §V-B, docs/odd-yaml.md): factors
// with their domains, abstraction into bins or classes, exposure priors and influence; the
// relevance predicate R_f and constraints; the malfunction modes M_f with their hazard regions;
// and the targets of the minimum scenario set (n_c, n_m, t, ε, δ, budget).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/core/expression.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/safety/model.hpp"

namespace emrm::scenario {

enum class FactorType { kContinuous, kInteger, kCategorical, kConstant };

/// One factor D_j with its abstraction α_j. Continuous and integer factors are cut into bins by
/// strictly increasing edges: bin k is [edges[k], edges[k+1]), the last bin is closed. A
/// categorical factor has classes, each with a number that predicates and the simulator see (its
/// index when none is given). A constant factor has one value and one level.
struct OddFactor {
  std::string name;
  std::string unit;
  FactorType type = FactorType::kContinuous;
  std::vector<double> edges;         ///< continuous and integer
  std::vector<double> kinks;         ///< safety-relevant values inside the domain (boundary seeds)
  std::vector<std::string> classes;  ///< categorical
  std::vector<double> class_values;  ///< categorical: the number of each class
  std::vector<double> prior;         ///< exposure per level, sums to 1
  bool influential = true;           ///< part of Q_f (t-wise coverage)
  double nominal = 0.0;              ///< value of the nominal scenario (HARA baseline)
  SourceLocation where;
  SourceLocation unit_where;                ///< the `unit:` entry as written (else `where`)
  std::vector<SourceLocation> value_where;  ///< each bin edge, class value (or name) or the constant value as written

  [[nodiscard]] int levels() const noexcept;
  /// Level of a value: its bin (values outside the domain are clamped into the first or last
  /// bin), or the class whose number equals it (nearest number otherwise).
  [[nodiscard]] int level_of(double value) const noexcept;
  /// "[44, 58)", "dry" or "10": a level as a reader sees it.
  [[nodiscard]] std::string level_label(int level) const;
  [[nodiscard]] double lower(int level) const noexcept;  ///< bin low edge, or the class value
  [[nodiscard]] double upper(int level) const noexcept;  ///< bin high edge, or the class value
  [[nodiscard]] double domain_min() const noexcept;
  [[nodiscard]] double domain_max() const noexcept;
  [[nodiscard]] bool is_numeric_range() const noexcept {
    return type == FactorType::kContinuous || type == FactorType::kInteger;
  }
};

/// A malfunction mode m ∈ M_f (normally a UCA of the safety case) with its hazard region
/// H_{f,m}, the hazards it leads to and the FSM transitions it exercises.
struct Malfunction {
  std::string id;
  std::string description;
  std::optional<core::Expression> region;  ///< none: the whole relevant domain
  std::vector<std::string> hazards;
  std::vector<std::string> transitions;  ///< "S3 -execute_maneuver-> S4"
  SourceLocation where;
};

/// What counts as a success Y(d) = 1 when a planned scenario is run.
enum class Acceptance { kAvoided, kMitigated };

/// The most points the manual baseline grid may have (the product of its factors' values): each is
/// a scenario whose coverage is measured against every cell.
inline constexpr std::size_t kMaxManualGridPoints = 100'000;

struct Odd {
  std::string file;
  std::string name;
  std::string description;
  std::vector<OddFactor> factors;
  std::optional<core::Expression> relevance;  ///< R_f; none = every point is relevant
  std::vector<core::Expression> constraints;  ///< every scenario satisfies all of them
  std::optional<core::Expression> tracked;    ///< cells with a precision target; none = all
  std::vector<Malfunction> malfunctions;
  /// Every hazard of the safety case; without one, the ODD's `hazards:` and those its modes name. A
  /// hazard a UCA names but the safety case lacks (a finding of `emrm analyze`) is not counted.
  std::vector<std::string> hazards;
  std::optional<std::filesystem::path> safety_file;  ///< as resolved against the ODD file
  std::optional<std::filesystem::path> scene_file;
  std::vector<std::string> strategies;           ///< for `emrm run`; empty = all
  std::vector<SourceLocation> strategies_where;  ///< each name as written (`emrm plan` checks them)
  std::string acceptance_strategy;               ///< empty = the registered chooser (resolved by `emrm run`)
  SourceLocation acceptance_where;               ///< the acceptance's strategy as written
  Acceptance acceptance = Acceptance::kAvoided;
  int strength = 2;           ///< t
  int n_c = 1;                ///< tests per cell (C1)
  int n_m = 3;                ///< tests per malfunction region (C4)
  double epsilon = 0.25;      ///< target Wilson half-width in tracked cells
  double delta = 0.05;        ///< 1 − confidence
  std::size_t budget = 1000;  ///< most scenarios the plan may hold
  std::uint64_t seed = 1;
  /// Manual baseline: the values of some factors (others at their nominal value); at most
  /// kMaxManualGridPoints points in all.
  std::vector<std::pair<std::size_t, std::vector<double>>> manual_grid;
  /// Total FSM transitions the transition coverage is measured against (empty: those the
  /// malfunctions name).
  std::vector<std::string> fsm_transitions;

  [[nodiscard]] std::vector<std::string> factor_names() const;
  [[nodiscard]] std::optional<std::size_t> factor_index(std::string_view name) const;
  /// Indices of the influential factors Q_f with more than one level.
  [[nodiscard]] std::vector<std::size_t> influential() const;
  /// α(d): the level of every factor.
  [[nodiscard]] std::vector<int> cell_of(std::span<const double> values) const;
  /// R_f(d) and every constraint.
  [[nodiscard]] bool admissible(std::span<const double> values) const;
  /// Number of cells of the abstract domain (product of levels).
  [[nodiscard]] double cell_count() const noexcept;
};

/// Checks an ODD, loaded or built in code: at least one factor; factor names that are identifiers
/// and unique; at least two strictly increasing bin edges (whole numbers for an integer factor),
/// kinks inside the domain, or classes that are unique with as many distinct numbers; a prior of
/// one probability >= 0 per level summing to 1; a nominal value in the domain; predicates compiled
/// over the factor names; strength 2 or 3 and no larger than the influential factors with more
/// than one level, n_c >= 1, n_m >= 0, epsilon in (0, 0.5), delta in (0, 1), budget >= 1; unique
/// malfunction ids; at most 200 000 cells; and some relevant cell (this computes relevant_cells).
/// Paths are written as in the file: "coverage.n_c", "factors[1].bins". Throws
/// core::ConfigError (an InputError): "odd: coverage.n_c: n_c must be >= 1, got 0".
void validate(const Odd& odd);

/// The levels of the scene's categorical factor `factor`, in index order (empty: the scene has no
/// categorical factor of that name), the scene being the one the ODD names (none: the default
/// scene). For a constant factor given by a level's name (`value: deer`): the ODD does not know the
/// simulator's families, so its caller supplies the lookup (workflow::family_levels).
using LevelLookup = std::function<std::vector<std::string>(const std::optional<std::filesystem::path>& scene_file,
                                                           const std::string& factor)>;

/// Loads an ODD file. Malfunction modes come from the file's `malfunctions:` list, or from the
/// UCAs of a safety case: `safety_override` when given, else the file's `safety:` entry. UCA
/// regions are recompiled against the ODD's factor names. Throws InputError (file:line:column)
/// for malformed YAML, unknown fields or types, keys that do not apply to a factor's type, an
/// unknown factor in a predicate, the default strength 2 without two influential factors, a bad
/// safety file, and for what validate() rejects, at the node of the field it names (each part is
/// checked as soon as it is read); UsageError when a named file does not exist.
/// With `levels`, a constant factor may be given by the name of a level of the scene's categorical
/// factor of its name (its index is the value); without, its value is a number.
[[nodiscard]] Odd load_odd(const std::filesystem::path& path,
                           const std::optional<std::filesystem::path>& safety_override = std::nullopt,
                           const LevelLookup& levels = nullptr);
/// As load_odd, from text; relative paths are resolved against `base_dir`.
[[nodiscard]] Odd parse_odd(const std::string& text, const std::string& file_name,
                            const std::filesystem::path& base_dir,
                            const std::optional<std::filesystem::path>& safety_override = std::nullopt,
                            const LevelLookup& levels = nullptr);

/// The malfunction modes of a safety case: one per UCA, its region recompiled against `factors`.
[[nodiscard]] std::vector<Malfunction> malfunctions_from(const safety::SafetyCase& sc,
                                                         const std::vector<std::string>& factors);

}  // namespace emrm::scenario

template <>
struct emrm::core::EnumNames<emrm::scenario::FactorType> {
  static constexpr std::array<std::pair<emrm::scenario::FactorType, std::string_view>, 4> kNames{
      {{emrm::scenario::FactorType::kContinuous, "continuous"},
       {emrm::scenario::FactorType::kInteger, "integer"},
       {emrm::scenario::FactorType::kCategorical, "categorical"},
       {emrm::scenario::FactorType::kConstant, "constant"}}};
};

template <>
struct emrm::core::EnumNames<emrm::scenario::Acceptance> {
  static constexpr std::array<std::pair<emrm::scenario::Acceptance, std::string_view>, 2> kNames{
      {{emrm::scenario::Acceptance::kAvoided, "avoided"}, {emrm::scenario::Acceptance::kMitigated, "mitigated"}}};
};
