#include "figure_parts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <string_view>

#include "emrm/sim/strategy.hpp"

namespace emrm::report::detail {

namespace fs = std::filesystem;
using campaign::CellRecord;

void write_csv(Figure& figure, const fs::path& dir, const core::Row& header, const std::vector<core::Row>& rows) {
  figure.csv = dir / (figure.name + ".csv");
  figure.png = dir / (figure.name + ".png");
  figure.svg = dir / (figure.name + ".svg");
  core::write_file(figure.csv, core::csv_table(header, rows));
}

double value_of(const CellRecord& r, Axis a) { return a.index < r.factors.size() ? r.factors[a.index] : 0.0; }

core::Row factor_columns(const sim::FactorTable& factors) { return factors.keys(); }

std::vector<double> distinct_values(const std::vector<CellRecord>& cells, Axis a) {
  std::vector<double> v;
  for (const auto& c : cells) v.push_back(value_of(c, a));
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end(), [](double x, double y) { return std::abs(x - y) <= kSameValue; }), v.end());
  return v;
}

namespace {

// Colours for strategies the registry does not know (a store written with a strategy registered
// then): the registered ones keep their record's colour in every figure.
constexpr std::array<std::string_view, 5> kExtraColours{"#8c564b", "#e377c2", "#17becf", "#bcbd22", "#d62728"};

}  // namespace

std::string strategy_label(std::string_view strategy) {
  const sim::StrategyTable registered = sim::registered_strategies();
  if (const sim::StrategyInfo* info = registered.info(strategy)) return info->label;
  std::string out(strategy);
  std::replace(out.begin(), out.end(), '_', ' ');
  return out;
}

std::string strategy_colour(std::string_view strategy, const std::vector<std::string>& strategies) {
  const sim::StrategyTable registered = sim::registered_strategies();
  if (const sim::StrategyInfo* info = registered.info(strategy)) return info->colour;
  std::size_t extra = 0;
  for (const auto& s : strategies) {
    if (s == strategy) break;
    if (registered.info(s) == nullptr) ++extra;
  }
  return std::string(kExtraColours[extra % kExtraColours.size()]);
}

std::string file_stem(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return out;
}

std::string StemSet::unique(std::string stem) {
  const std::string base = stem;
  for (int n = 2; !taken_.insert(stem).second; ++n) stem = fmt::format("{}_{}", base, n);
  return stem;
}

bool is_o_or_r(const CellRecord& c) {
  return c.feasible && (c.region == sim::Region::kO || c.region == sim::Region::kR);
}
bool is_undecided(const CellRecord& c) { return is_o_or_r(c) && c.evidence == campaign::CellEvidence::kUndecided; }

}  // namespace emrm::report::detail
