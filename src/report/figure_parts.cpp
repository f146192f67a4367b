#include "figure_parts.hpp"

#include <algorithm>
#include <cmath>

namespace emrm::report::detail {

namespace fs = std::filesystem;
using campaign::CellRecord;

void write_csv(Figure& figure, const fs::path& dir, const core::Row& header, const std::vector<core::Row>& rows) {
  figure.csv = dir / (figure.name + ".csv");
  figure.png = dir / (figure.name + ".png");
  figure.svg = dir / (figure.name + ".svg");
  core::write_file(figure.csv, core::csv_table(header, rows));
}

double value_of(const CellRecord& r, Axis a) {
  switch (a) {
    case Axis::kSpeed:
      return r.speed_kph;
    case Axis::kTtc:
      return r.ttc_s;
    case Axis::kMu:
      return r.mu;
    case Axis::kPassage:
      return r.passage_m;
    case Axis::kTruckSpeed:
      return r.truck_speed_kph;
  }
  return 0.0;
}

std::vector<double> distinct_values(const std::vector<CellRecord>& cells, Axis a) {
  std::vector<double> v;
  for (const auto& c : cells) v.push_back(value_of(c, a));
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end(), [](double x, double y) { return std::abs(x - y) <= kSameValue; }), v.end());
  return v;
}

bool is_o_or_r(const CellRecord& c) { return c.feasible && (c.region == "O" || c.region == "R"); }
bool is_undecided(const CellRecord& c) { return is_o_or_r(c) && c.evidence == "undecided"; }

}  // namespace emrm::report::detail
