#pragma once

// The factors of a scenario (docs/architecture.md, "The factor table"): one table per scenario
// names each factor once, with its key, unit, labels, limits and default, and says which of them
// the method itself reads (the ego's speed, the time to collision, the road's friction: the maps'
// axes and the analytic stop boundary). Everything else — the campaign reader, the ODD checks, the
// store's columns, the exports, the maps, the adaptive search, the MPI wire and Python — iterates
// the table, so adding a factor to a scenario edits that scenario's own files and nothing else.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/core/enum_names.hpp"

namespace emrm::sim {

/// The most factors a scenario may have.
inline constexpr std::size_t kMaxFactors = 8;

/// What a factor means to the method (not to its scenario). The first three are every
/// scenario's first three factors, in this order (kMethodFactors): the maps, the stop boundary, the
/// adaptive search and the tables read them there.
enum class FactorRole : std::uint8_t {
  kEgoSpeed,  ///< the ego's speed when the hazard appears, km/h: the maps' ordinate, the stop boundary
  kTtc,       ///< the time to collision when the hazard appears, s: the maps' abscissa
  kFriction,  ///< the road's friction coefficient: the maps' panels, the stop boundary
  kPassage,   ///< the width left to pass the hazard, m (optional): the tables' narrow and wide passages
  kOther,     ///< the scenario's own (an obstacle's speed)
};

/// The factors every scenario has, first in its cells: ego speed, TTC, friction.
inline constexpr std::size_t kEgoSpeedFactor = 0, kTtcFactor = 1, kFrictionFactor = 2, kMethodFactors = 3;

/// The values a factor accepts: finite, above `low` (or equal to it with `low_inclusive`), at most
/// `high`, and a whole number when `whole` (a categorical factor's level).
struct FactorLimits {
  double low = 0.0;
  bool low_inclusive = false;
  double high = std::numeric_limits<double>::infinity();
  bool whole = false;

  [[nodiscard]] bool accepts(double value) const noexcept {
    return std::isfinite(value) && (low_inclusive ? value >= low : value > low) && value <= high &&
           (!whole || value == std::floor(value));
  }
  [[nodiscard]] bool operator==(const FactorLimits&) const = default;
  /// The limits of a categorical factor of `levels` levels: 0, 1, ..., levels - 1.
  [[nodiscard]] static FactorLimits categorical(std::size_t levels) noexcept {
    return {.low = 0.0, .low_inclusive = true, .high = static_cast<double>(levels) - 1.0, .whole = true};
  }
};

/// One factor of a scenario. A factor is a number (a speed, a width) or categorical (the kind of an
/// obstacle, the roadside): a categorical factor names its `levels`, and a cell holds the index of
/// one (0, 1, ...); campaigns, ODDs and `--factor` name the level, the maps and texts show it.
struct Factor {
  std::string key{};     ///< as campaigns, ODDs, stores, exports and Python name it ("mu")
  std::string unit{};    ///< "km/h", "s", "1" (a plain number), "m"
  std::string what{};    ///< "friction coefficient": in messages
  std::string axis{};    ///< "road friction μ (–)": a figure's axis
  std::string plural{};  ///< "μ": how a figure's note counts its values
  std::string held{};    ///< "μ = {}": a map panel's held value ({} is the value, or the level's name)
  std::string brief{};   ///< "mu {:g}": the value in `emrm simulate`'s text ({} for a categorical factor's level)
  FactorRole role = FactorRole::kOther;
  double default_value = 0.0;         ///< a cell's value when a grid or a command does not set it
  FactorLimits limits{};              ///< the values a cell may hold
  std::string why_high{};             ///< why there is an upper limit, when the scene sets it
  double band = 0.05;                 ///< half the width of a map cell when the factor takes one value only
  std::string name{};                 ///< "μ": short, in summaries ("speed × μ × passage")
  std::vector<std::string> levels{};  ///< a categorical factor's levels, by index; empty for a number

  [[nodiscard]] bool categorical() const noexcept { return !levels.empty(); }
  [[nodiscard]] bool accepts(double value) const noexcept { return limits.accepts(value); }
  /// The index of the level `level_name`, or none (also for a factor that is a number).
  [[nodiscard]] std::optional<std::size_t> level(std::string_view level_name) const noexcept;
  /// A value as the user writes it: the level's name for a categorical factor, else the number.
  [[nodiscard]] std::string value_text(double value) const;
  /// `pattern` (`held`, `brief`) with the value in it: a categorical factor's level by name.
  [[nodiscard]] std::string format(std::string_view pattern, double value) const;
  /// A value as a user gave it: a level's name (a categorical factor) or a number. Throws UsageError
  /// naming the factor and what it accepts.
  [[nodiscard]] double parse(std::string_view text) const;
  /// "0 < mu <= 2", "speed_kph > 0", "truck_speed_kph >= 0", "obstacle one of truck, deer".
  [[nodiscard]] std::string inequality() const;
  /// The message for a value accepts() refuses: "mu must be a finite friction coefficient with 0 < mu <= 2, got 3",
  /// and the likely slip behind it (slip_hint).
  [[nodiscard]] std::string refusal(double value) const;
  /// The likely slip behind a refused value, or "": "a percentage?" for a plain number above its
  /// limit and within a hundred times it (μ 50), else why_high for any value above the limit.
  [[nodiscard]] std::string slip_hint(double value) const;
};

/// The factor values of one scenario cell, in the order of its scenario's table. A small value:
/// cheap to copy, compared and hashed value by value.
class CellInput {
 public:
  CellInput() = default;
  CellInput(std::initializer_list<double> values);
  explicit CellInput(std::span<const double> values);

  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  [[nodiscard]] double operator[](std::size_t i) const noexcept { return values_[i]; }
  [[nodiscard]] double& operator[](std::size_t i) noexcept { return values_[i]; }
  [[nodiscard]] std::span<const double> values() const noexcept { return {values_.data(), size_}; }
  [[nodiscard]] const double* begin() const noexcept { return values_.data(); }
  [[nodiscard]] const double* end() const noexcept { return values_.data() + size_; }
  [[nodiscard]] bool operator==(const CellInput& other) const noexcept;

  /// The method's factors (FactorRole; a scenario's first three).
  [[nodiscard]] double ego_speed_kph() const noexcept { return values_[kEgoSpeedFactor]; }
  [[nodiscard]] double time_to_collision_s() const noexcept { return values_[kTtcFactor]; }
  [[nodiscard]] double friction() const noexcept { return values_[kFrictionFactor]; }

 private:
  std::array<double, kMaxFactors> values_{};
  std::size_t size_ = 0;
};

/// A scenario's factors, in cell order.
class FactorTable {
 public:
  FactorTable() = default;  ///< no factor
  /// Throws std::logic_error (a scenario's programming error) for more than kMaxFactors factors,
  /// a key given twice, a role other than kOther given twice, or a table whose first three factors
  /// are not the ego's speed, the TTC and the friction, in that order. A default may lie outside its
  /// limits (a passage wider than a narrow road): a cell that keeps it is refused by validate().
  explicit FactorTable(std::vector<Factor> factors);

  [[nodiscard]] std::size_t size() const noexcept { return factors_.size(); }
  [[nodiscard]] const Factor& operator[](std::size_t i) const noexcept { return factors_[i]; }
  [[nodiscard]] auto begin() const noexcept { return factors_.begin(); }
  [[nodiscard]] auto end() const noexcept { return factors_.end(); }
  /// The position of the factor `key`, or none.
  [[nodiscard]] std::optional<std::size_t> find(std::string_view key) const noexcept;
  /// The position of the factor with `role`, or none when the scenario has no such factor.
  [[nodiscard]] std::optional<std::size_t> find(FactorRole role) const noexcept;
  /// The keys, in cell order.
  [[nodiscard]] std::vector<std::string> keys() const;
  /// "speed_kph, ttc_s, mu, ...": for messages.
  [[nodiscard]] std::string key_list() const;
  /// A cell with every factor at its default.
  [[nodiscard]] CellInput defaults() const;
  /// Sets factor `key` of `cell`; false when the scenario has no factor of that name.
  bool set(CellInput& cell, std::string_view key, double value) const;
  /// Checks a cell: one value per factor, each accepted. Throws UsageError naming the factor and
  /// its accepted range.
  void validate(const CellInput& cell) const;

 private:
  std::vector<Factor> factors_;
};

/// The highest ego speed (km/h) and friction coefficient a cell of any family may have: above every
/// road vehicle and every road, so that a value beyond is another unit.
inline constexpr double kMaxEgoSpeed_kph = 400.0;
inline constexpr double kMaxFriction = 2.0;
/// Why a speed has that limit (a Factor's `why_high`).
inline constexpr std::string_view kWhyMaxSpeed = "faster than any road vehicle drives; the speed is in km/h";

/// The method's three factors (the ego's speed, the TTC, the friction: kMethodFactors) with the keys,
/// labels and limits every family shares, at the family's defaults: the start of its factor table.
[[nodiscard]] std::vector<Factor> method_factors(double speed_kph, double ttc_s, double mu);

/// A categorical factor (FactorRole::kOther) named `key`, described as `what` in messages and
/// figures, with its `levels` in index order; the first is the default.
[[nodiscard]] Factor categorical_factor(std::string key, const std::string& what, std::vector<std::string> levels);

/// A cell in words, each factor by its `brief`: "50 km/h, TTC 1 s, mu 1, passage 3 m, truck 10 km/h".
[[nodiscard]] std::string cell_text(const FactorTable& factors, const CellInput& cell);

}  // namespace emrm::sim

/// The roles' names: in the tables' breakdowns ("by speed") and in `emrm families --json`.
template <>
struct emrm::core::EnumNames<emrm::sim::FactorRole> {
  static constexpr std::array<std::pair<emrm::sim::FactorRole, std::string_view>, 5> kNames{{
      {emrm::sim::FactorRole::kEgoSpeed, "speed"},
      {emrm::sim::FactorRole::kTtc, "ttc"},
      {emrm::sim::FactorRole::kFriction, "friction"},
      {emrm::sim::FactorRole::kPassage, "passage"},
      {emrm::sim::FactorRole::kOther, "other"},
  }};
};
