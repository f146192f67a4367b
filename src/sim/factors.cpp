#include "emrm/sim/factors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "emrm/core/error.hpp"

namespace emrm::sim {

std::string Factor::inequality() const {
  const std::string_view op = limits.low_inclusive ? "<=" : "<";
  if (std::isinf(limits.high)) return fmt::format("{} {} {:g}", key, limits.low_inclusive ? ">=" : ">", limits.low);
  return fmt::format("{:g} {} {} <= {:g}", limits.low, op, key, limits.high);
}

std::string Factor::refusal(double value) const {
  return fmt::format("{} must be a finite {} with {}{}, got {}{}", key, what, inequality(),
                     unit == "1" ? "" : " " + unit, value,
                     value > limits.high && !why_high.empty() ? ": " + why_high : std::string());
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

std::string cell_text(const FactorTable& factors, const CellInput& cell) {
  std::vector<std::string> values;
  for (std::size_t i = 0; i < factors.size() && i < cell.size(); ++i)
    values.push_back(fmt::format(fmt::runtime(factors[i].brief), cell[i]));
  return fmt::format("{}", fmt::join(values, ", "));
}

}  // namespace emrm::sim
