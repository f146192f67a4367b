#include "emrm/sim/factors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"

namespace emrm::sim {

std::string Factor::inequality() const {
  if (categorical()) return fmt::format("{} one of {}", key, fmt::join(levels, ", "));
  const std::string_view op = limits.low_inclusive ? "<=" : "<";
  if (std::isinf(limits.high)) return fmt::format("{} {} {:g}", key, limits.low_inclusive ? ">=" : ">", limits.low);
  return fmt::format("{:g} {} {} <= {:g}", limits.low, op, key, limits.high);
}

std::string Factor::refusal(double value) const {
  if (categorical()) {
    std::vector<std::string> indexed;
    for (std::size_t i = 0; i < levels.size(); ++i) indexed.push_back(fmt::format("{} ({})", levels[i], i));
    return fmt::format("{} must be one of the levels {}, got {}", key, fmt::join(indexed, ", "), value);
  }
  const std::string slip = slip_hint(value);
  return fmt::format("{} must be a finite {} with {}{}, got {}{}", key, what, inequality(),
                     unit == "1" ? "" : " " + unit, value, slip.empty() ? std::string() : "; " + slip);
}

std::string Factor::slip_hint(double value) const {
  if (categorical() || !(value > limits.high)) return "";
  if (unit == "1" && value <= 100.0 * limits.high) return "a percentage?";
  return why_high;
}

std::optional<std::size_t> Factor::level(std::string_view level_name) const noexcept {
  for (std::size_t i = 0; i < levels.size(); ++i)
    if (levels[i] == level_name) return i;
  return std::nullopt;
}

std::string Factor::value_text(double value) const {
  if (categorical() && accepts(value)) return levels[static_cast<std::size_t>(value)];
  return fmt::format("{:g}", value);
}

std::string Factor::format(std::string_view pattern, double value) const {
  if (categorical() && accepts(value))
    return fmt::format(fmt::runtime(pattern), levels[static_cast<std::size_t>(value)]);
  return fmt::format(fmt::runtime(pattern), value);
}

double Factor::parse(std::string_view text) const {
  if (categorical()) {
    if (const auto i = level(text)) return static_cast<double>(*i);
    throw UsageError(fmt::format("{} is one of {}, got '{}'", key, fmt::join(levels, ", "), text));
  }
  if (const auto value = core::parse_finite_number(std::string(text))) return *value;
  throw UsageError(
      fmt::format("{} expects a finite number{}, got '{}'", key, unit == "1" ? "" : " (" + unit + ")", text));
}

CellInput::CellInput(std::initializer_list<double> values)
    : CellInput(std::span<const double>(values.begin(), values.size())) {}

CellInput::CellInput(std::span<const double> values) : size_(values.size()) {
  if (values.size() > kMaxFactors)
    throw std::logic_error(fmt::format("a cell of {} factors: at most {} are supported", values.size(), kMaxFactors));
  std::copy(values.begin(), values.end(), values_.begin());
}

bool CellInput::operator==(const CellInput& other) const noexcept {
  return size_ == other.size_ && std::equal(begin(), end(), other.begin());
}

FactorTable::FactorTable(std::vector<Factor> factors) : factors_(std::move(factors)) {
  if (factors_.size() > kMaxFactors)
    throw std::logic_error(
        fmt::format("a scenario of {} factors: at most {} are supported", factors_.size(), kMaxFactors));
  constexpr std::array<FactorRole, kMethodFactors> kFirst{FactorRole::kEgoSpeed, FactorRole::kTtc,
                                                          FactorRole::kFriction};
  for (std::size_t i = 0; i < kMethodFactors; ++i)
    if (i >= factors_.size() || factors_[i].role != kFirst[i])
      throw std::logic_error("a scenario's first three factors are the ego's speed, the TTC and the friction");
  for (std::size_t i = 0; i < factors_.size(); ++i) {
    const Factor& f = factors_[i];
    for (std::size_t j = 0; j < i; ++j) {
      if (factors_[j].key == f.key) throw std::logic_error(fmt::format("factor '{}' given twice", f.key));
      if (f.role != FactorRole::kOther && factors_[j].role == f.role)
        throw std::logic_error(fmt::format("factors '{}' and '{}' have the same role", factors_[j].key, f.key));
    }
    if (f.categorical() && (f.role != FactorRole::kOther || f.limits != FactorLimits::categorical(f.levels.size())))
      throw std::logic_error(
          fmt::format("categorical factor '{}': role 'other' and FactorLimits::categorical's limits", f.key));
  }
}

std::optional<std::size_t> FactorTable::find(std::string_view key) const noexcept {
  for (std::size_t i = 0; i < factors_.size(); ++i)
    if (factors_[i].key == key) return i;
  return std::nullopt;
}

std::optional<std::size_t> FactorTable::find(FactorRole role) const noexcept {
  for (std::size_t i = 0; i < factors_.size(); ++i)
    if (factors_[i].role == role) return i;
  return std::nullopt;
}

std::vector<std::string> FactorTable::keys() const {
  std::vector<std::string> out;
  out.reserve(factors_.size());
  for (const Factor& f : factors_) out.push_back(f.key);
  return out;
}

std::string FactorTable::key_list() const { return fmt::format("{}", fmt::join(keys(), ", ")); }

CellInput FactorTable::defaults() const {
  std::vector<double> values;
  values.reserve(factors_.size());
  for (const Factor& f : factors_) values.push_back(f.default_value);
  return CellInput(std::span<const double>(values));
}

bool FactorTable::set(CellInput& cell, std::string_view key, double value) const {
  const auto i = find(key);
  if (!i || *i >= cell.size()) return false;
  cell[*i] = value;
  return true;
}

void FactorTable::validate(const CellInput& cell) const {
  if (cell.size() != factors_.size())
    throw UsageError(
        fmt::format("a cell of {} values for the {} factors {}", cell.size(), factors_.size(), key_list()));
  for (std::size_t i = 0; i < factors_.size(); ++i)
    if (!factors_[i].accepts(cell[i])) throw UsageError(factors_[i].refusal(cell[i]));
}

std::vector<Factor> method_factors(double speed_kph, double ttc_s, double mu) {
  std::vector<Factor> factors(kMethodFactors);
  factors[kEgoSpeedFactor] = {.key = "speed_kph",
                              .unit = "km/h",
                              .what = "ego speed",
                              .axis = "ego speed (km/h)",
                              .plural = "speeds",
                              .held = "v = {} km/h",
                              .brief = "{:g} km/h",
                              .role = FactorRole::kEgoSpeed,
                              .default_value = speed_kph,
                              .limits = {.high = kMaxEgoSpeed_kph},
                              .why_high = std::string(kWhyMaxSpeed),
                              .band = 1.0,
                              .name = "speed"};
  factors[kTtcFactor] = {.key = "ttc_s",
                         .unit = "s",
                         .what = "time to collision",
                         .axis = "time to collision TTC (s)",
                         .plural = "TTCs",
                         .held = "TTC = {} s",
                         .brief = "TTC {:g} s",
                         .role = FactorRole::kTtc,
                         .default_value = ttc_s,
                         .name = "TTC"};
  factors[kFrictionFactor] = {.key = "mu",
                              .unit = "1",
                              .what = "friction coefficient",
                              .axis = "road friction μ (–)",
                              .plural = "μ",
                              .held = "μ = {}",
                              .brief = "mu {:g}",
                              .role = FactorRole::kFriction,
                              .default_value = mu,
                              .limits = {.high = kMaxFriction},
                              .name = "μ"};
  return factors;
}

Factor categorical_factor(std::string key, const std::string& what, std::vector<std::string> levels) {
  const FactorLimits limits = FactorLimits::categorical(levels.size());
  return {.key = std::move(key),
          .unit = "",
          .what = what,
          .axis = what,
          .plural = what + "s",
          .held = "{}",
          .brief = "{}",
          .default_value = 0.0,
          .limits = limits,
          .band = 0.5,
          .name = what,
          .levels = std::move(levels)};
}

std::string cell_text(const FactorTable& factors, const CellInput& cell) {
  std::vector<std::string> values;
  for (std::size_t i = 0; i < factors.size() && i < cell.size(); ++i)
    values.push_back(factors[i].format(factors[i].brief, cell[i]));
  return fmt::format("{}", fmt::join(values, ", "));
}

}  // namespace emrm::sim
