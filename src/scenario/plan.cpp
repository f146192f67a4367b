#include "emrm/scenario/plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "emrm/core/random.hpp"
#include "emrm/core/text.hpp"
#include "emrm/scenario/covering_array.hpp"
#include "emrm/scenario/statistics.hpp"
#include "odd_rules.hpp"

namespace emrm::scenario {

std::string cell_key(const std::vector<int>& cell) {
  std::string key = "c";
  for (std::size_t i = 0; i < cell.size(); ++i) key += (i ? "." : "") + std::to_string(cell[i]);
  return key;
}

namespace {

constexpr int kRandomProbes = 16;  // seeded interior points tried per cell for relevance
constexpr int kSampleTries = 256;  // uniform draws per request for a point inside a cell

// Values are rounded to a grid fine against their bin (1/100 of its width, as a power of ten, at
// most 1e-3) so that scenario files stay readable: 51.3 km/h, 0.532 s.
double resolution(const OddFactor& f, int level) {
  const double width = f.upper(level) - f.lower(level);
  return std::min(1e-3, std::pow(10.0, std::floor(std::log10(width / 100.0))));
}

// The largest representable value of a bin: its closed top for the last bin, one resolution step
// (or one integer) below the next edge otherwise.
double top_inside(const OddFactor& f, int level) {
  if (level + 1 == f.levels()) return f.upper(level);
  if (f.type == FactorType::kInteger) return f.upper(level) - 1.0;
  return f.upper(level) - resolution(f, level);
}

double round_into(const OddFactor& f, int level, double v) {
  if (f.type == FactorType::kInteger) return std::clamp(std::floor(v), f.lower(level), top_inside(f, level));
  if (!f.is_numeric_range()) return v;
  const double g = resolution(f, level);
  return std::clamp(std::round(v / g) * g, f.lower(level), top_inside(f, level));
}

// A uniform draw inside one level of a factor.
double draw(const OddFactor& f, int level, std::mt19937_64& rng) {
  if (f.type == FactorType::kInteger) {
    const auto count = static_cast<std::uint64_t>(top_inside(f, level) - f.lower(level)) + 1;
    return f.lower(level) + static_cast<double>(core::uniform_index(rng, count));
  }
  if (!f.is_numeric_range()) return f.lower(level);
  return round_into(f, level, f.lower(level) + core::uniform01(rng) * (f.upper(level) - f.lower(level)));
}

// Centre, corners (when there are at most 10 ranged factors) and random points of a cell.
std::vector<std::vector<double>> probes(const Odd& odd, const std::vector<int>& cell) {
  std::vector<std::vector<double>> points;
  std::vector<double> centre(odd.factors.size());
  std::vector<std::size_t> ranged;
  for (std::size_t i = 0; i < odd.factors.size(); ++i) {
    const OddFactor& f = odd.factors[i];
    centre[i] = round_into(f, cell[i], 0.5 * (f.lower(cell[i]) + f.upper(cell[i])));
    if (f.is_numeric_range()) ranged.push_back(i);
  }
  points.push_back(centre);
  if (ranged.size() <= 10) {
    for (std::size_t mask = 0; mask < (std::size_t{1} << ranged.size()); ++mask) {
      std::vector<double> corner = centre;
      for (std::size_t b = 0; b < ranged.size(); ++b) {
        const OddFactor& f = odd.factors[ranged[b]];
        const int level = cell[ranged[b]];
        corner[ranged[b]] = (mask >> b) & 1U ? top_inside(f, level) : f.lower(level);
      }
      points.push_back(std::move(corner));
    }
  }
  std::mt19937_64 rng(core::derive_seed(odd.seed, "probe " + cell_key(cell)));
  for (int r = 0; r < kRandomProbes; ++r) {
    std::vector<double> p(odd.factors.size());
    for (std::size_t i = 0; i < odd.factors.size(); ++i) p[i] = draw(odd.factors[i], cell[i], rng);
    points.push_back(std::move(p));
  }
  return points;
}

std::string point_key(const std::vector<double>& values) {
  std::vector<std::string> parts;
  for (double v : values) parts.push_back(fmt::format("{:.9g}", v));
  return core::join(parts, " ");
}

bool in_region(const Malfunction& m, const std::vector<double>& values) { return !m.region || m.region->holds(values); }

// The builder's state: the scenarios so far, their count per relevant cell, a random stream.
class PlanBuilder {
 public:
  explicit PlanBuilder(const Odd& odd)
      : odd_(odd), cells_(detail::validated_relevant_cells(odd)), rng_(core::derive_seed(odd.seed, "plan")) {
    for (std::size_t c = 0; c < cells_.size(); ++c) index_.emplace(cells_[c].levels, c);
    counts_.assign(cells_.size(), 0);
  }

  const std::vector<RelevantCell>& cells() const { return cells_; }
  const std::vector<std::size_t>& counts() const { return counts_; }
  std::vector<Scenario>& scenarios() { return scenarios_; }

  // Adds an admissible point unless it is already planned; says whether it was added.
  bool add(const std::vector<double>& values, const std::string& step) {
    if (!seen_.insert(point_key(values)).second) return false;
    Scenario s;
    s.step = step;
    s.values = values;
    s.cell = odd_.cell_of(values);
    classify(odd_, values, s.malfunctions, s.transitions);
    s.seed = core::derive_seed(odd_.seed, point_key(values));
    if (auto it = index_.find(s.cell); it != index_.end()) ++counts_[it->second];
    scenarios_.push_back(std::move(s));
    return true;
  }

  // A new admissible point inside cell `c`, with factor `fixed` at `fixed_value` if given, for
  // which `extra` holds: random draws first, then the cell's probe points.
  // With `anywhere`, the point may leave the cell (a bin edge pinned from the bin below it).
  template <class Predicate>
  std::optional<std::vector<double>> sample(std::size_t c, std::optional<std::size_t> fixed, double fixed_value,
                                            Predicate extra, bool anywhere = false) {
    const auto ok = [&](std::vector<double>& p) {
      if (fixed) p[*fixed] = fixed_value;
      return (anywhere || odd_.cell_of(p) == cells_[c].levels) && odd_.admissible(p) && extra(p) &&
             !seen_.count(point_key(p));
    };
    const std::vector<int>& levels = cells_[c].levels;
    for (int t = 0; t < kSampleTries; ++t) {
      std::vector<double> p(odd_.factors.size());
      for (std::size_t i = 0; i < p.size(); ++i) p[i] = draw(odd_.factors[i], levels[i], rng_);
      if (ok(p)) return p;
    }
    // Where the admissible part of the cell is a sliver, draws between the cell's witness and a
    // uniform point, most of them close to the witness, still find it.
    const std::vector<double>& w = cells_[c].witness;
    for (int t = 0; t < kSampleTries; ++t) {
      const double s = std::pow(core::uniform01(rng_), 3.0);
      std::vector<double> p(odd_.factors.size());
      for (std::size_t i = 0; i < p.size(); ++i) {
        const OddFactor& f = odd_.factors[i];
        p[i] = f.is_numeric_range() ? round_into(f, levels[i], w[i] + s * (draw(f, levels[i], rng_) - w[i])) : w[i];
      }
      if (ok(p)) return p;
    }
    for (auto p : probes(odd_, levels))
      if (ok(p)) return p;
    return std::nullopt;
  }

  // Relevant cells with `factor` at `level` (any level when factor is none), fewest tests first.
  std::vector<std::size_t> least_tested(std::optional<std::size_t> factor = std::nullopt, int level = 0) const {
    std::vector<std::size_t> order;
    for (std::size_t c = 0; c < cells_.size(); ++c)
      if (!factor || cells_[c].levels[*factor] == level) order.push_back(c);
    std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return counts_[a] < counts_[b]; });
    return order;
  }

  std::optional<std::size_t> cell_index(const std::vector<int>& levels) const {
    auto it = index_.find(levels);
    return it == index_.end() ? std::nullopt : std::optional<std::size_t>(it->second);
  }

  std::mt19937_64& rng() { return rng_; }

 private:
  const Odd& odd_;
  std::vector<RelevantCell> cells_;
  std::map<std::vector<int>, std::size_t> index_;
  std::vector<std::size_t> counts_;
  std::vector<Scenario> scenarios_;
  std::set<std::string> seen_;
  std::mt19937_64 rng_;
};

constexpr auto kAnyPoint = [](const std::vector<double>&) { return true; };

std::string target_label(const Odd& odd, const BoundaryTarget& t) {
  const OddFactor& f = odd.factors[t.factor];
  if (f.type == FactorType::kCategorical)
    return f.name + " = " + f.classes[static_cast<std::size_t>(f.level_of(t.value))];
  return fmt::format("{} = {:g}", f.name, t.value);
}

bool hits(const std::vector<Scenario>& scenarios, const BoundaryTarget& t) {
  return std::any_of(scenarios.begin(), scenarios.end(),
                     [&](const Scenario& s) { return s.values[t.factor] == t.value; });
}

// Step 1 (C2): every bin edge, kink and class in some test; a test takes as many pending
// targets of other factors as stay admissible.
std::size_t boundary_seed(const Odd& odd, PlanBuilder& b, Plan& plan) {
  const auto targets = boundary_targets(odd);
  std::vector<const BoundaryTarget*> unreachable;
  std::size_t added = 0;
  for (const auto& t : targets) {
    if (hits(b.scenarios(), t)) continue;
    const OddFactor& f = odd.factors[t.factor];
    const int level = f.level_of(t.value);
    std::optional<std::vector<double>> point;
    for (std::size_t c : b.least_tested(t.factor, level))
      if ((point = b.sample(c, t.factor, t.value, kAnyPoint))) break;
    // An edge closes the bin below it too: the checker counts a point there as reaching it.
    if (!point && f.is_numeric_range() && level > 0 && t.value == f.lower(level))
      for (std::size_t c : b.least_tested(t.factor, level - 1))
        if ((point = b.sample(c, t.factor, t.value, kAnyPoint, true))) break;
    if (!point) {
      unreachable.push_back(&t);
      continue;
    }
    // Other pending targets join the test while it stays admissible and in a relevant cell.
    for (const auto& other : targets) {
      if (other.factor == t.factor || (*point)[other.factor] == other.value || hits(b.scenarios(), other) ||
          std::find(unreachable.begin(), unreachable.end(), &other) != unreachable.end())
        continue;
      std::vector<double> trial = *point;
      trial[other.factor] = other.value;
      if (odd.admissible(trial) && b.cell_index(odd.cell_of(trial))) point = std::move(trial);
    }
    added += b.add(*point, "boundary") ? 1 : 0;
  }
  for (const auto* t : unreachable)
    if (!hits(b.scenarios(), *t)) plan.infeasible.push_back("boundary " + target_label(odd, *t));
  return added;
}

// Step 2 (C3): a covering array of strength t over the influential factors, seeded with the
// tests so far; level combinations no relevant cell has are constraints.
std::size_t combinatorial_core(const Odd& odd, PlanBuilder& b) {
  const auto q = odd.influential();
  if (q.size() < static_cast<std::size_t>(odd.strength)) return 0;
  std::vector<int> levels;
  for (auto i : q) levels.push_back(odd.factors[i].levels());
  std::set<std::vector<int>> projections;
  for (const auto& cell : b.cells()) {
    std::vector<int> p;
    for (auto i : q) p.push_back(cell.levels[i]);
    projections.insert(std::move(p));
  }
  const std::vector<std::vector<int>> admissible(projections.begin(), projections.end());
  const RowViolates violates = [&admissible](std::span<const int> row) {
    return std::none_of(admissible.begin(), admissible.end(), [&](const std::vector<int>& p) {
      for (std::size_t k = 0; k < row.size(); ++k)
        if (row[k] != kDontCare && row[k] != p[k]) return false;
      return true;
    });
  };
  CoveringArrayOptions options;
  options.strength = odd.strength;
  options.seed = core::derive_seed(odd.seed, "covering array");
  std::set<std::vector<int>> seeds;
  for (const auto& s : b.scenarios()) {
    std::vector<int> p;
    for (auto i : q) p.push_back(s.cell[i]);
    if (projections.count(p)) seeds.insert(std::move(p));
  }
  options.seed_rows.assign(seeds.begin(), seeds.end());
  const CoveringArray ca = generate_covering_array(levels, options, violates);

  std::size_t added = 0;
  for (std::size_t r = options.seed_rows.size(); r < ca.rows.size(); ++r) {
    const auto& row = ca.rows[r];
    for (std::size_t c : b.least_tested()) {
      bool match = true;
      for (std::size_t k = 0; k < q.size() && match; ++k) match = b.cells()[c].levels[q[k]] == row[k];
      if (!match) continue;
      if (auto p = b.sample(c, std::nullopt, 0.0, kAnyPoint)) {
        added += b.add(*p, "covering_array") ? 1 : 0;
        break;
      }
    }
  }
  return added;
}

// The factors' domains as a reader sees them: "mu in [0.1, 1]", "road in {dry, wet}", "truck = 10".
std::string domains_text(const Odd& odd, const std::vector<std::string>& names) {
  std::vector<std::string> parts;
  for (const auto& name : names) {
    const OddFactor& f = odd.factors[*odd.factor_index(name)];
    if (f.type == FactorType::kConstant)
      parts.push_back(fmt::format("{} = {:g}", f.name, f.nominal));
    else if (f.type == FactorType::kCategorical)
      parts.push_back(fmt::format("{} in {{{}}}", f.name, core::join(f.classes, ", ")));
    else
      parts.push_back(fmt::format("{} in [{:g}, {:g}]", f.name, f.domain_min(), f.domain_max()));
  }
  return core::join(parts, ", ");
}

// Calls visit(levels) for every cell of the abstract domain, in odometer order (the last factor
// varies fastest).
template <class Visit>
void for_each_cell(const Odd& odd, Visit visit) {
  std::vector<int> levels(odd.factors.size(), 0);
  for (bool more = !odd.factors.empty(); more;) {
    visit(levels);
    more = false;
    for (std::size_t i = levels.size(); i-- > 0;) {
      if (++levels[i] < odd.factors[i].levels()) {
        more = true;
        break;
      }
      levels[i] = 0;
    }
  }
}

// Why a mode's region holds at no admissible point, as far as the probes of every cell of the
// domain show: nowhere in the factors' domains, or only where R_f or a constraint fails. None when
// a probe finds an admissible point of the region (then the region is not empty, only hard to hit).
std::optional<std::string> why_region_empty(const Odd& odd, const Malfunction& m) {
  if (!m.region) return std::nullopt;
  bool in_domain = false, relevant = false, admissible = false;
  std::vector<bool> kept(odd.constraints.size(), false);
  for_each_cell(odd, [&](const std::vector<int>& levels) {
    for (const auto& p : probes(odd, levels)) {
      if (!m.region->holds(p)) continue;
      in_domain = true;
      relevant = relevant || !odd.relevance || odd.relevance->holds(p);
      admissible = admissible || odd.admissible(p);
      for (std::size_t k = 0; k < kept.size(); ++k) kept[k] = kept[k] || odd.constraints[k].holds(p);
    }
  });
  const std::string region = "'" + m.region->text() + "'";
  if (admissible) return std::nullopt;
  if (!in_domain)
    return fmt::format("{} holds nowhere in the factors' domains ({})", region,
                       domains_text(odd, m.region->used_variables()));
  if (!relevant) return fmt::format("{} holds only where the relevance rule '{}' fails", region, odd.relevance->text());
  for (std::size_t k = 0; k < kept.size(); ++k)
    if (!kept[k])
      return fmt::format("{} holds only where the constraint '{}' fails", region, odd.constraints[k].text());
  return fmt::format("{} holds only where the relevance rule or some constraint fails", region);
}

// The shortfall of mode `m` with `have` tests after the allocation gave up: an empty region when
// no cell had a point of it and the probes say why.
Shortfall malfunction_shortfall(const Odd& odd, const Malfunction& m, std::size_t have, bool searched_everywhere) {
  const auto needed = static_cast<std::size_t>(odd.n_m);
  if (have == 0 && searched_everywhere)
    if (auto why = why_region_empty(odd, m))
      return {ShortfallKind::kEmptyRegion, m.id, have, needed,
              fmt::format("malfunction {}: its region is empty inside the ODD: {}; no test can exercise it (C4 "
                          "needs {})",
                          m.id, *why, needed)};
  return {ShortfallKind::kTooFewTests, m.id, have, needed,
          fmt::format("malfunction {}: only {} of {} tests found in its region", m.id, have, needed)};
}

// Step 3 (C4): n_m tests inside each malfunction's hazard region, in the least-tested cells.
std::size_t malfunction_allocation(const Odd& odd, PlanBuilder& b, Plan& plan) {
  std::size_t added = 0;
  for (const auto& m : odd.malfunctions) {
    const auto in_m = [&m](const std::vector<double>& p) { return in_region(m, p); };
    const auto count_in = [&] {
      return static_cast<int>(
          std::count_if(b.scenarios().begin(), b.scenarios().end(), [&](const Scenario& s) { return in_m(s.values); }));
    };
    std::set<std::size_t> outside;  // cells where no point of the region was found
    for (int have = count_in(); have < odd.n_m; have = count_in()) {
      bool placed = false;
      for (std::size_t c : b.least_tested()) {
        if (outside.count(c)) continue;
        if (auto p = b.sample(c, std::nullopt, 0.0, in_m)) {
          placed = b.add(*p, "malfunction");
          added += placed ? 1 : 0;
          break;
        }
        outside.insert(c);
      }
      if (!placed) {
        plan.shortfalls.push_back(
            malfunction_shortfall(odd, m, static_cast<std::size_t>(have), outside.size() == b.cells().size()));
        break;
      }
    }
  }
  return added;
}

// Step 4a (C1): n_c tests in every relevant cell.
std::size_t cell_fill(const Odd& odd, PlanBuilder& b, Plan& plan) {
  std::size_t added = 0;
  for (std::size_t c = 0; c < b.cells().size(); ++c) {
    while (b.counts()[c] < static_cast<std::size_t>(odd.n_c)) {
      auto p = b.sample(c, std::nullopt, 0.0, kAnyPoint);
      if (!p || !b.add(*p, "cell_fill")) {
        const std::string key = cell_key(b.cells()[c].levels);
        plan.shortfalls.push_back(
            {ShortfallKind::kTooFewPoints, key, b.counts()[c], static_cast<std::size_t>(odd.n_c),
             fmt::format("cell {}: only {} distinct admissible points found", key, b.counts()[c])});
        break;
      }
      ++added;
    }
  }
  return added;
}

// Step 4b: tracked cells drawn with probability ∝ √π until each has `target` tests or the budget
// is spent. Returns the number of tracked cells still short.
std::size_t top_up(const Odd& odd, PlanBuilder& b, std::size_t target, std::size_t& added) {
  std::set<std::size_t> exhausted;
  const auto short_cells = [&] {
    std::vector<std::size_t> out;
    for (std::size_t c = 0; c < b.cells().size(); ++c)
      if (b.cells()[c].tracked && b.counts()[c] < target && !exhausted.count(c)) out.push_back(c);
    return out;
  };
  for (auto open = short_cells(); !open.empty() && b.scenarios().size() < odd.budget; open = short_cells()) {
    double total = 0.0;
    for (auto c : open) total += std::sqrt(b.cells()[c].prior);
    double u = core::uniform01(b.rng()) * total;
    std::size_t pick = open.back();
    for (auto c : open) {
      u -= std::sqrt(b.cells()[c].prior);
      if (u < 0.0) {
        pick = c;
        break;
      }
    }
    auto p = b.sample(pick, std::nullopt, 0.0, kAnyPoint);
    if (p && b.add(*p, "top_up"))
      ++added;
    else
      exhausted.insert(pick);
  }
  std::size_t still_short = 0;
  for (std::size_t c = 0; c < b.cells().size(); ++c)
    if (b.cells()[c].tracked && b.counts()[c] < target) ++still_short;
  return still_short;
}

std::string shortfall_messages(const Plan& plan) {
  std::vector<std::string> messages;
  for (const auto& s : plan.shortfalls) messages.push_back(s.message);
  return core::join(messages, "; ");
}

}  // namespace

std::vector<RelevantCell> relevant_cells(const Odd& odd) {
  if (odd.cell_count() > 200000)
    throw InputError(SourceLocation{odd.file, 1, 1},
                     fmt::format("the factors' levels make {:.0f} cells, more than 200000", odd.cell_count()));
  std::vector<RelevantCell> cells;
  for_each_cell(odd, [&](const std::vector<int>& levels) {
    RelevantCell cell{levels, {}, 1.0, false};
    for (auto& p : probes(odd, levels)) {
      if (!odd.admissible(p)) continue;
      if (cell.witness.empty()) cell.witness = p;
      if (!odd.tracked || odd.tracked->holds(p)) {
        cell.tracked = true;
        break;
      }
    }
    if (cell.witness.empty()) return;
    for (std::size_t i = 0; i < levels.size(); ++i)
      cell.prior *= odd.factors[i].prior[static_cast<std::size_t>(levels[i])];
    cells.push_back(std::move(cell));
  });
  double total = 0.0;
  for (const auto& c : cells) total += c.prior;
  for (auto& c : cells) c.prior = total > 0.0 ? c.prior / total : 1.0 / static_cast<double>(cells.size());
  return cells;
}

std::vector<BoundaryTarget> boundary_targets(const Odd& odd) {
  std::vector<BoundaryTarget> targets;
  for (std::size_t i = 0; i < odd.factors.size(); ++i) {
    const OddFactor& f = odd.factors[i];
    std::vector<double> values;
    if (f.is_numeric_range()) {
      values = f.edges;
      values.insert(values.end(), f.kinks.begin(), f.kinks.end());
    } else if (f.type == FactorType::kCategorical) {
      values = f.class_values;
    }
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
    for (double v : values) targets.push_back({i, v});
  }
  return targets;
}

void classify(const Odd& odd, const std::vector<double>& values, std::vector<std::string>& malfunctions,
              std::vector<std::string>& transitions) {
  malfunctions.clear();
  transitions.clear();
  for (const auto& m : odd.malfunctions) {
    if (!in_region(m, values)) continue;
    malfunctions.push_back(m.id);
    for (const auto& t : m.transitions)
      if (std::find(transitions.begin(), transitions.end(), t) == transitions.end()) transitions.push_back(t);
  }
}

Plan build_plan(const Odd& odd) {
  Plan plan;
  PlanBuilder b(odd);
  plan.relevant_cells = b.cells().size();
  plan.tracked_cells = static_cast<std::size_t>(
      std::count_if(b.cells().begin(), b.cells().end(), [](const RelevantCell& c) { return c.tracked; }));
  plan.tests_per_tracked_cell =
      std::max<std::size_t>(wilson_sample_size(odd.epsilon, 1.0 - odd.delta), static_cast<std::size_t>(odd.n_c));

  plan.steps.push_back({"boundary", boundary_seed(odd, b, plan), "bin edges, kinks and classes (C2)"});
  plan.steps.push_back({"covering_array", combinatorial_core(odd, b),
                        fmt::format("strength {} over the influential factors (C3)", odd.strength)});
  plan.steps.push_back({"malfunction", malfunction_allocation(odd, b, plan),
                        fmt::format("{} tests in each of {} hazard regions (C4)", odd.n_m, odd.malfunctions.size())});
  plan.steps.push_back({"cell_fill", cell_fill(odd, b, plan),
                        fmt::format("{} test(s) in each of {} relevant cells (C1)", odd.n_c, b.cells().size())});
  const std::size_t coverage_size = b.scenarios().size();
  std::size_t added = 0;
  const std::size_t short_cells = top_up(odd, b, plan.tests_per_tracked_cell, added);
  plan.steps.push_back(
      {"top_up", added,
       fmt::format("q ∝ √π over {} tracked cells to {} tests each (worst-case Wilson half-width "
                   "≤ {:g} at {:g} %)",
                   plan.tracked_cells, plan.tests_per_tracked_cell, odd.epsilon, 100.0 * (1.0 - odd.delta))});

  // Step 5: why the construction stopped.
  plan.targets_met = plan.shortfalls.empty() && short_cells == 0;
  if (plan.targets_met)
    plan.stop_reason = fmt::format(
        "targets met: C1-C4 hold and every tracked cell has {} tests (worst-case Wilson half-width <= {:g})",
        plan.tests_per_tracked_cell, odd.epsilon);
  else if (short_cells > 0 && b.scenarios().size() >= odd.budget)
    plan.stop_reason = fmt::format("budget of {} scenarios spent{}: {} tracked cells have fewer than {} tests",
                                   odd.budget, coverage_size > odd.budget ? " by the coverage constraints alone" : "",
                                   short_cells, plan.tests_per_tracked_cell);
  else
    plan.stop_reason =
        fmt::format("targets not met: {}{}",
                    short_cells ? fmt::format("{} tracked cells have too few distinct admissible points{}", short_cells,
                                              plan.shortfalls.empty() ? "" : "; ")
                                : std::string(),
                    shortfall_messages(plan));

  // Weights w = π(cell) / q(cell) with q the plan's own cell frequencies; ids in plan order.
  auto& scenarios = b.scenarios();
  const double n = static_cast<double>(scenarios.size());
  const int width = std::max<int>(3, static_cast<int>(std::to_string(scenarios.size()).size()));
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    Scenario& s = scenarios[i];
    s.id = fmt::format("S{:0{}}", i + 1, width);
    const auto c = b.cell_index(s.cell);
    s.weight = c ? b.cells()[*c].prior * n / static_cast<double>(b.counts()[*c]) : 0.0;
  }
  plan.scenarios = std::move(scenarios);
  plan.cells = b.cells();
  return plan;
}

}  // namespace emrm::scenario
