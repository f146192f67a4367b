#include "emrm/scenario/coverage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "emrm/core/error.hpp"
#include "emrm/core/random.hpp"
#include "emrm/scenario/plan.hpp"
#include "odd_rules.hpp"

// Deliberately self-contained: everything below is recomputed from the points and the ODD's
// definitions (cells, predicates, regions), so a bookkeeping bug in build_plan cannot hide here.

namespace emrm::scenario {
namespace {

using Point = std::vector<double>;

constexpr double kRelativeTolerance = 1e-9;
constexpr std::size_t kMaxCornerFactors = 10;  // 2^10 corners per cell at most
constexpr int kFeasibilityProbes = 256;        // random points per cell and boundary target
constexpr int kBaselineProbes = 64;            // random points per cell and mode (STPA baseline)

bool same_value(double a, double b) {
  return a == b || std::abs(a - b) <= kRelativeTolerance * std::max(std::abs(a), std::abs(b));
}

// A value the factor can take: inside a numeric domain (an integer for integer factors), one of the
// classes, or the constant.
bool in_domain(const OddFactor& f, double v) {
  if (!std::isfinite(v)) return false;
  switch (f.type) {
    case FactorType::kContinuous:
      return (v >= f.domain_min() || same_value(v, f.domain_min())) &&
             (v <= f.domain_max() || same_value(v, f.domain_max()));
    case FactorType::kInteger:
      return v == std::round(v) && v >= f.domain_min() && v <= f.domain_max();
    case FactorType::kCategorical:
      return std::any_of(f.class_values.begin(), f.class_values.end(), [&](double c) { return same_value(v, c); });
    case FactorType::kConstant:
      return same_value(v, f.nominal);
  }
  return false;
}

// A point of the ODD's domain where R_f and every constraint hold.
bool admissible(const Odd& odd, const Point& p) {
  for (std::size_t i = 0; i < odd.factors.size(); ++i)
    if (!in_domain(odd.factors[i], p[i])) return false;
  return odd.admissible(p);
}

bool in_region(const Malfunction& m, const Point& p) { return !m.region || m.region->holds(p); }

void add_unique(std::vector<std::string>& list, const std::string& item) {
  if (std::find(list.begin(), list.end(), item) == list.end()) list.push_back(item);
}

// The values factor `f` can take inside one of its levels, as a closed range [low, high]
// (a single value for classes and constants).
struct LevelRange {
  double low;
  double high;
};
LevelRange range_of(const OddFactor& f, int level) { return {f.lower(level), f.upper(level)}; }

double snap(const OddFactor& f, double v) { return f.type == FactorType::kInteger ? std::round(v) : v; }

double draw(const OddFactor& f, LevelRange r, std::mt19937_64& rng) {
  if (r.high <= r.low) return r.low;
  if (f.type == FactorType::kInteger) {
    const auto count = static_cast<std::uint64_t>(std::floor(r.high) - std::ceil(r.low)) + 1;
    return std::ceil(r.low) + static_cast<double>(core::uniform_index(rng, count));
  }
  return r.low + core::uniform01(rng) * (r.high - r.low);
}

// Candidate points of one cell, `fixed` factor (if any) pinned to its value: the centre, the point
// of the cell nearest the nominal point, the corners (when at most kMaxCornerFactors factors are
// ranged) and `random_points` uniform draws. Calls `visit` on each until it returns true.
template <class Visit>
bool probe_cell(const Odd& odd, const std::vector<int>& cell, std::optional<std::pair<std::size_t, double>> fixed,
                int random_points, std::mt19937_64& rng, Visit visit) {
  const std::size_t n = odd.factors.size();
  std::vector<LevelRange> ranges(n);
  std::vector<std::size_t> ranged;
  for (std::size_t i = 0; i < n; ++i) {
    ranges[i] = range_of(odd.factors[i], cell[i]);
    if (fixed && fixed->first == i) ranges[i] = {fixed->second, fixed->second};
    if (ranges[i].high > ranges[i].low) ranged.push_back(i);
  }
  Point centre(n);
  Point near_nominal(n);
  for (std::size_t i = 0; i < n; ++i) {
    const OddFactor& f = odd.factors[i];
    centre[i] = std::clamp(snap(f, 0.5 * (ranges[i].low + ranges[i].high)), ranges[i].low, ranges[i].high);
    near_nominal[i] = std::clamp(snap(f, f.nominal), ranges[i].low, ranges[i].high);
  }
  if (visit(centre) || visit(near_nominal)) return true;
  if (ranged.size() <= kMaxCornerFactors) {
    for (std::size_t mask = 0; mask < (std::size_t{1} << ranged.size()); ++mask) {
      Point corner = centre;
      for (std::size_t b = 0; b < ranged.size(); ++b)
        corner[ranged[b]] = (mask >> b) & 1U ? ranges[ranged[b]].high : ranges[ranged[b]].low;
      if (visit(corner)) return true;
    }
  }
  for (int r = 0; r < random_points; ++r) {
    Point p(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = draw(odd.factors[i], ranges[i], rng);
    if (visit(p)) return true;
  }
  return false;
}

// Does value `v` of factor `f` lie in `level` (closed at both ends, so an edge belongs to both
// neighbouring bins for the search)?
bool level_contains(const OddFactor& f, int level, double v) {
  if (f.is_numeric_range()) {
    const LevelRange r = range_of(f, level);
    return (v >= r.low || same_value(v, r.low)) && (v <= r.high || same_value(v, r.high));
  }
  return f.level_of(v) == level;
}

std::string target_label(const OddFactor& f, double v) {
  if (f.type == FactorType::kCategorical) return f.name + " = " + f.classes[static_cast<std::size_t>(f.level_of(v))];
  return fmt::format("{} = {:g}", f.name, v);
}

// Can the checker itself find an admissible point with factor j at v?
bool boundary_feasible(const Odd& odd, const std::vector<RelevantCell>& cells, const BoundaryTarget& t) {
  const OddFactor& f = odd.factors[t.factor];
  std::mt19937_64 rng(core::derive_seed(odd.seed, fmt::format("coverage boundary {} {:.17g}", f.name, t.value)));
  for (const RelevantCell& c : cells) {
    if (!level_contains(f, c.levels[t.factor], t.value)) continue;
    if (probe_cell(odd, c.levels, std::pair{t.factor, t.value}, kFeasibilityProbes, rng,
                   [&](const Point& p) { return admissible(odd, p); }))
      return true;
  }
  return false;
}

CoverageCount count_hazards(const Odd& odd, const std::vector<const Point*>& points) {
  std::vector<std::string> total;
  for (const auto& h : odd.hazards) add_unique(total, h);
  CoverageCount count;
  count.total = total.size();
  for (const auto& h : total) {
    const bool covered = std::any_of(odd.malfunctions.begin(), odd.malfunctions.end(), [&](const Malfunction& m) {
      return std::find(m.hazards.begin(), m.hazards.end(), h) != m.hazards.end() &&
             std::any_of(points.begin(), points.end(), [&](const Point* p) { return in_region(m, *p); });
    });
    if (covered) {
      ++count.covered;
    } else {
      count.missing.push_back(h);
    }
  }
  return count;
}

CoverageCount count_transitions(const Odd& odd, const std::vector<const Point*>& points) {
  std::vector<std::string> total;
  if (!odd.fsm_transitions.empty()) {
    for (const auto& t : odd.fsm_transitions) add_unique(total, t);
  } else {
    for (const auto& m : odd.malfunctions)
      for (const auto& t : m.transitions) add_unique(total, t);
  }
  CoverageCount count;
  count.total = total.size();
  for (const auto& t : total) {
    const bool covered = std::any_of(odd.malfunctions.begin(), odd.malfunctions.end(), [&](const Malfunction& m) {
      return std::find(m.transitions.begin(), m.transitions.end(), t) != m.transitions.end() &&
             std::any_of(points.begin(), points.end(), [&](const Point* p) { return in_region(m, *p); });
    });
    if (covered) {
      ++count.covered;
    } else {
      count.missing.push_back(t);
    }
  }
  return count;
}

// Visits every t-subset of {0, …, n−1} in lexicographic order.
template <class Visit>
void for_each_subset(std::size_t n, std::size_t t, Visit visit) {
  if (t == 0 || t > n) return;
  std::vector<std::size_t> idx(t);
  for (std::size_t i = 0; i < t; ++i) idx[i] = i;
  while (true) {
    visit(idx);
    std::size_t i = t;
    while (i > 0 && idx[i - 1] == n - t + (i - 1)) --i;
    if (i == 0) return;
    ++idx[i - 1];
    for (std::size_t k = i; k < t; ++k) idx[k] = idx[k - 1] + 1;
  }
}

// The level combinations of `factors` that some relevant cell has, and of those, the ones some
// admissible point realises (every combination is enumerated, in odometer order).
void count_tuples(const Odd& odd, const std::vector<std::size_t>& factors, const std::vector<RelevantCell>& cells,
                  const std::vector<std::vector<int>>& point_cells, CoverageCount& count) {
  const auto project = [&](const std::vector<int>& cell) {
    std::vector<int> tuple;
    tuple.reserve(factors.size());
    for (std::size_t j : factors) tuple.push_back(cell[j]);
    return tuple;
  };
  std::set<std::vector<int>> realisable;
  for (const auto& c : cells) realisable.insert(project(c.levels));
  std::set<std::vector<int>> realised;
  for (const auto& c : point_cells) realised.insert(project(c));
  std::vector<int> tuple(factors.size(), 0);
  for (bool more = true; more;) {
    if (realisable.count(tuple)) {
      ++count.total;
      if (realised.count(tuple)) {
        ++count.covered;
      } else {
        std::string label;
        for (std::size_t k = 0; k < factors.size(); ++k) {
          const OddFactor& f = odd.factors[factors[k]];
          label += (k ? ", " : "") + f.name + " " + f.level_label(tuple[k]);
        }
        count.missing.push_back(std::move(label));
      }
    }
    more = false;
    for (std::size_t k = factors.size(); k-- > 0;) {
      if (++tuple[k] < odd.factors[factors[k]].levels()) {
        more = true;
        break;
      }
      tuple[k] = 0;
    }
  }
}

CoverageCount count_twise(const Odd& odd, const std::vector<RelevantCell>& cells,
                          const std::vector<std::vector<int>>& point_cells) {
  CoverageCount count;
  const std::vector<std::size_t> q = odd.influential();
  if (odd.strength <= 0) return count;
  for_each_subset(q.size(), static_cast<std::size_t>(odd.strength), [&](const std::vector<std::size_t>& pick) {
    std::vector<std::size_t> factors;
    factors.reserve(pick.size());
    for (std::size_t k : pick) factors.push_back(q[k]);
    count_tuples(odd, factors, cells, point_cells, count);
  });
  return count;
}

nlohmann::ordered_json count_json(const CoverageCount& c) {
  nlohmann::ordered_json j;
  j["covered"] = c.covered;
  j["total"] = c.total;
  j["fraction"] = c.fraction();
  j["missing"] = c.missing;
  return j;
}

// Reading a report back: InputError names the file and the field's place in the document (JSON
// carries no line numbers once parsed).
[[noreturn]] void malformed(const std::string& file, const std::string& where, std::string_view expected) {
  throw InputError({file, 0, 0}, fmt::format("{}: expected {}", where, expected));
}

const nlohmann::ordered_json& field_of(const nlohmann::ordered_json& j, const std::string& key, const std::string& file,
                                       const std::string& where) {
  if (!j.is_object()) malformed(file, where, "an object");
  const auto it = j.find(key);
  if (it == j.end()) malformed(file, where + "." + key, "a value, found none");
  return *it;
}

// The field `key` of `j` as a T (a count, a flag or a name).
template <class T>
T value_of(const nlohmann::ordered_json& j, const std::string& key, const std::string& file, const std::string& where) {
  const auto& v = field_of(j, key, file, where);
  if constexpr (std::is_same_v<T, bool>) {
    if (!v.is_boolean()) malformed(file, where + "." + key, "true or false");
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!v.is_string()) malformed(file, where + "." + key, "a string");
  } else {
    static_assert(std::is_same_v<T, std::size_t>);
    if (!v.is_number_unsigned()) malformed(file, where + "." + key, "a non-negative integer");
  }
  return v.get<T>();
}

CoverageCount count_from_json(const nlohmann::ordered_json& parent, const std::string& key, const std::string& file,
                              const std::string& where) {
  const std::string at = where + "." + key;
  const auto& j = field_of(parent, key, file, where);
  CoverageCount c;
  c.covered = value_of<std::size_t>(j, "covered", file, at);
  c.total = value_of<std::size_t>(j, "total", file, at);
  const auto& missing = field_of(j, "missing", file, at);
  if (!missing.is_array()) malformed(file, at + ".missing", "a list of strings");
  for (const auto& m : missing) {
    if (!m.is_string()) malformed(file, at + ".missing", "a list of strings");
    c.missing.push_back(m.get<std::string>());
  }
  return c;
}

}  // namespace

CoverageReport measure_coverage(const Odd& odd, const std::vector<std::vector<double>>& points, std::string name) {
  // Validates the ODD first; its relevant cells are those the coverage of cells is measured over.
  const std::vector<RelevantCell> cells = detail::validated_relevant_cells(odd);
  CoverageReport report;
  report.name = std::move(name);
  report.scenarios = points.size();

  std::vector<const Point*> valid;
  std::vector<std::vector<int>> valid_cells;
  for (const Point& p : points) {
    if (p.size() != odd.factors.size())
      throw std::invalid_argument(
          fmt::format("measure_coverage: a point has {} values, the ODD {} factors", p.size(), odd.factors.size()));
    if (!admissible(odd, p)) {
      ++report.inadmissible;
      continue;
    }
    valid.push_back(&p);
    valid_cells.push_back(odd.cell_of(p));
  }

  report.hazards = count_hazards(odd, valid);
  report.transitions = count_transitions(odd, valid);

  report.c4 = true;
  report.malfunctions.total = odd.malfunctions.size();
  for (const Malfunction& m : odd.malfunctions) {
    const auto inside = std::count_if(valid.begin(), valid.end(), [&](const Point* p) { return in_region(m, *p); });
    report.tests_per_malfunction.emplace_back(m.id, static_cast<std::size_t>(inside));
    if (inside > 0) {
      ++report.malfunctions.covered;
    } else {
      report.malfunctions.missing.push_back(m.id);
    }
    if (inside < odd.n_m) report.c4 = false;
  }

  report.c1 = true;
  report.cells.total = cells.size();
  for (const RelevantCell& c : cells) {
    const auto tests = std::count(valid_cells.begin(), valid_cells.end(), c.levels);
    if (tests > 0) {
      ++report.cells.covered;
    } else {
      report.cells.missing.push_back(cell_key(c.levels));
    }
    if (tests < odd.n_c) report.c1 = false;
  }

  for (const BoundaryTarget& t : boundary_targets(odd)) {
    const bool hit =
        std::any_of(valid.begin(), valid.end(), [&](const Point* p) { return same_value((*p)[t.factor], t.value); });
    if (!hit && !boundary_feasible(odd, cells, t)) continue;  // infeasible targets do not count
    ++report.boundaries.total;
    if (hit) {
      ++report.boundaries.covered;
    } else {
      report.boundaries.missing.push_back(target_label(odd.factors[t.factor], t.value));
    }
  }
  report.c2 = report.boundaries.covered == report.boundaries.total;

  report.twise = count_twise(odd, cells, valid_cells);
  report.c3 = report.twise.covered == report.twise.total;
  return report;
}

std::vector<double> nominal_point(const Odd& odd) {
  std::vector<double> p;
  p.reserve(odd.factors.size());
  for (const auto& f : odd.factors) p.push_back(f.nominal);
  return p;
}

std::vector<std::vector<double>> hara_only_baseline(const Odd& odd) {
  return std::vector<std::vector<double>>(odd.hazards.size(), nominal_point(odd));
}

std::vector<std::vector<double>> stpa_only_baseline(const Odd& odd) {
  const Point nominal = nominal_point(odd);
  const auto distance2 = [&](const Point& p) {
    double d = 0.0;
    for (std::size_t i = 0; i < odd.factors.size(); ++i) {
      const double width = odd.factors[i].domain_max() - odd.factors[i].domain_min();
      if (width > 0.0) d += std::pow((p[i] - nominal[i]) / width, 2);
    }
    return d;
  };
  const std::vector<RelevantCell> cells = relevant_cells(odd);
  std::vector<std::vector<double>> scenarios;
  for (const Malfunction& m : odd.malfunctions) {
    std::optional<Point> best;
    double best_distance = std::numeric_limits<double>::infinity();
    const auto consider = [&](const Point& p) {
      if (!admissible(odd, p) || !in_region(m, p)) return false;
      const double d = distance2(p);
      if (d < best_distance) {
        best_distance = d;
        best = p;
      }
      return d == 0.0;  // nothing is nearer than the nominal point itself
    };
    std::mt19937_64 rng(core::derive_seed(odd.seed, "coverage stpa baseline " + m.id));
    if (!consider(nominal)) {
      for (const RelevantCell& c : cells)
        if (probe_cell(odd, c.levels, std::nullopt, kBaselineProbes, rng, consider)) break;
    }
    if (best) scenarios.push_back(std::move(*best));
  }
  return scenarios;
}

std::vector<std::vector<double>> manual_baseline(const Odd& odd) {
  if (odd.manual_grid.empty()) return {};
  for (const auto& [factor, values] : odd.manual_grid)
    if (values.empty()) return {};
  std::vector<std::vector<double>> scenarios;
  std::vector<std::size_t> index(odd.manual_grid.size(), 0);
  for (bool more = true; more;) {
    Point p = nominal_point(odd);
    for (std::size_t k = 0; k < index.size(); ++k) p[odd.manual_grid[k].first] = odd.manual_grid[k].second[index[k]];
    scenarios.push_back(std::move(p));
    // Odometer: the last listed factor varies fastest.
    more = false;
    for (std::size_t k = index.size(); k-- > 0;) {
      if (++index[k] < odd.manual_grid[k].second.size()) {
        more = true;
        break;
      }
      index[k] = 0;
    }
  }
  return scenarios;
}

nlohmann::ordered_json to_json(const CoverageReport& report) {
  nlohmann::ordered_json j;
  j["name"] = report.name;
  j["scenarios"] = report.scenarios;
  j["inadmissible"] = report.inadmissible;
  j["hazards"] = count_json(report.hazards);
  j["malfunctions"] = count_json(report.malfunctions);
  nlohmann::ordered_json per_mode = nlohmann::ordered_json::object();
  for (const auto& [id, n] : report.tests_per_malfunction) per_mode[id] = n;
  j["tests_per_malfunction"] = per_mode;
  j["transitions"] = count_json(report.transitions);
  j["cells"] = count_json(report.cells);
  j["boundaries"] = count_json(report.boundaries);
  j["twise"] = count_json(report.twise);
  j["c1"] = report.c1;
  j["c2"] = report.c2;
  j["c3"] = report.c3;
  j["c4"] = report.c4;
  j["all"] = report.all();
  return j;
}

CoverageReport coverage_report_from_json(const nlohmann::ordered_json& j, const std::string& file,
                                         const std::string& where) {
  CoverageReport report;
  report.name = value_of<std::string>(j, "name", file, where);
  report.scenarios = value_of<std::size_t>(j, "scenarios", file, where);
  report.inadmissible = value_of<std::size_t>(j, "inadmissible", file, where);
  report.hazards = count_from_json(j, "hazards", file, where);
  report.malfunctions = count_from_json(j, "malfunctions", file, where);
  const auto& per_mode = field_of(j, "tests_per_malfunction", file, where);
  if (!per_mode.is_object()) malformed(file, where + ".tests_per_malfunction", "an object of test counts");
  for (const auto& mode : per_mode.items())
    report.tests_per_malfunction.emplace_back(
        mode.key(), value_of<std::size_t>(per_mode, mode.key(), file, where + ".tests_per_malfunction"));
  report.transitions = count_from_json(j, "transitions", file, where);
  report.cells = count_from_json(j, "cells", file, where);
  report.boundaries = count_from_json(j, "boundaries", file, where);
  report.twise = count_from_json(j, "twise", file, where);
  report.c1 = value_of<bool>(j, "c1", file, where);
  report.c2 = value_of<bool>(j, "c2", file, where);
  report.c3 = value_of<bool>(j, "c3", file, where);
  report.c4 = value_of<bool>(j, "c4", file, where);
  return report;
}

}  // namespace emrm::scenario
