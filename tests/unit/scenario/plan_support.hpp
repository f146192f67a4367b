#pragma once

// What the plan tests share: the shipped ODD and plan, the invariants every plan must satisfy
// (checked against an independent enumeration), and seeded random ODDs written as YAML.

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "emrm/scenario/coverage.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/plan.hpp"
#include "emrm/scenario/statistics.hpp"
#include "odd_support.hpp"

namespace emrm::scenario::test_support {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

inline const Odd& shipped_odd() {
  static const Odd odd = load_odd(examples_dir() / "odd.yaml");
  return odd;
}

inline const Plan& shipped_plan() {
  static const Plan plan = build_plan(shipped_odd());
  return plan;
}

inline std::vector<std::vector<double>> points_of(const Plan& plan) {
  std::vector<std::vector<double>> points;
  for (const auto& s : plan.scenarios) points.push_back(s.values);
  return points;
}

inline std::string describe(const CoverageReport& r) {
  std::string out = fmt::format("C1 {} C2 {} C3 {} C4 {}; inadmissible {}", r.c1, r.c2, r.c3, r.c4, r.inadmissible);
  for (const auto& m : r.cells.missing) out += "\n  cell missing " + m;
  for (const auto& m : r.boundaries.missing) out += "\n  boundary missing " + m;
  for (const auto& m : r.twise.missing) out += "\n  tuple missing " + m;
  for (const auto& m : r.malfunctions.missing) out += "\n  mode missing " + m;
  return out;
}

inline std::string describe(const Plan& plan) {
  std::string out = fmt::format("{} scenarios; {}", plan.scenarios.size(), plan.stop_reason);
  for (const auto& s : plan.infeasible) out += "\n  infeasible " + s;
  for (const auto& s : plan.shortfalls) out += "\n  shortfall " + s.message;
  return out;
}

// π(cell) from the factors' priors, renormalised over the relevant cells; computed here, not taken
// from the planner.
inline std::map<std::vector<int>, double> cell_priors(const Odd& odd) {
  std::map<std::vector<int>, double> priors;
  double total = 0.0;
  for (const auto& c : relevant_cells(odd)) {
    double p = 1.0;
    for (std::size_t i = 0; i < odd.factors.size(); ++i)
      p *= odd.factors[i].prior[static_cast<std::size_t>(c.levels[i])];
    priors[c.levels] = p;
    total += p;
  }
  for (auto& [cell, p] : priors) p = total > 0.0 ? p / total : 1.0 / static_cast<double>(priors.size());
  return priors;
}

// Every admissible point of an ODD without continuous factors (none when it has one, or too many).
inline std::optional<std::vector<std::vector<double>>> all_admissible_points(const Odd& odd) {
  std::vector<std::vector<double>> values;
  double total = 1.0;
  for (const auto& f : odd.factors) {
    std::vector<double> v;
    if (f.type == FactorType::kContinuous) return std::nullopt;
    if (f.type == FactorType::kInteger)
      for (double x = f.domain_min(); x <= f.domain_max(); x += 1.0) v.push_back(x);
    if (f.type == FactorType::kCategorical) v = f.class_values;
    if (f.type == FactorType::kConstant) v = {f.nominal};
    total *= static_cast<double>(v.size());
    values.push_back(std::move(v));
  }
  if (total > 20000) return std::nullopt;
  std::vector<std::vector<double>> points;
  std::vector<std::size_t> index(values.size(), 0);
  for (bool more = true; more;) {
    std::vector<double> p;
    for (std::size_t i = 0; i < values.size(); ++i) p.push_back(values[i][index[i]]);
    if (odd.admissible(p)) points.push_back(std::move(p));
    more = false;
    for (std::size_t i = values.size(); i-- > 0;) {
      if (++index[i] < values[i].size()) {
        more = true;
        break;
      }
      index[i] = 0;
    }
  }
  return points;
}

inline bool reported(const Plan& plan, const std::string& prefix) {
  return std::any_of(plan.shortfalls.begin(), plan.shortfalls.end(),
                     [&](const Shortfall& s) { return s.message.rfind(prefix, 0) == 0; });
}

// On a finite domain the planner's shortfalls can be checked exactly: a mode or cell falls short only
// when the domain holds too few admissible points, and then the plan holds all of them.
inline void expect_shortfalls_are_real(const Odd& odd, const Plan& plan) {
  const auto all = all_admissible_points(odd);
  if (!all) return;
  const auto in = [](const Malfunction& m, const std::vector<double>& p) { return !m.region || m.region->holds(p); };
  for (const auto& m : odd.malfunctions) {
    const auto available = std::count_if(all->begin(), all->end(), [&](const auto& p) { return in(m, p); });
    const auto planned =
        std::count_if(plan.scenarios.begin(), plan.scenarios.end(), [&](const Scenario& s) { return in(m, s.values); });
    EXPECT_GE(planned, std::min<long>(available, odd.n_m)) << m.id;
    EXPECT_EQ(reported(plan, "malfunction " + m.id + ":"), available < odd.n_m)
        << m.id << ": " << available << " points";
  }
  std::map<std::vector<int>, long> available, planned;
  for (const auto& p : *all) ++available[odd.cell_of(p)];
  for (const auto& s : plan.scenarios) ++planned[s.cell];
  for (const auto& c : relevant_cells(odd)) {
    const long a = available[c.levels];
    EXPECT_GE(planned[c.levels], std::min<long>(a, odd.n_c)) << cell_key(c.levels);
    EXPECT_EQ(reported(plan, "cell " + cell_key(c.levels) + ":"), a < odd.n_c) << cell_key(c.levels) << ": " << a;
    // A tracked cell short of its target (with budget left) holds every point there is.
    if (c.tracked && plan.scenarios.size() < odd.budget &&
        planned[c.levels] < static_cast<long>(plan.tests_per_tracked_cell)) {
      EXPECT_EQ(planned[c.levels], a) << cell_key(c.levels);
    }
  }
}

// Every property of a plan that holds whatever the ODD: traceability, identity, weights, and
// (when the planner reports no shortfall) C1–C4 by the independent checker.
inline void expect_plan_invariants(const Odd& odd, const Plan& plan) {
  const std::size_t n = plan.scenarios.size();
  ASSERT_GT(n, 0u);
  const auto report = measure_coverage(odd, points_of(plan), "plan");
  EXPECT_EQ(report.inadmissible, 0u) << "every scenario must be admissible and inside the domain";
  if (plan.shortfalls.empty()) {
    EXPECT_TRUE(report.c1) << describe(report) << "\n" << describe(plan);
    EXPECT_TRUE(report.c2) << describe(report) << "\n" << describe(plan);
    EXPECT_TRUE(report.c3) << describe(report) << "\n" << describe(plan);
    EXPECT_TRUE(report.c4) << describe(report) << "\n" << describe(plan);
  }

  // Ids S001, S002, … in plan order (at least three digits).
  const int width = std::max<int>(3, static_cast<int>(std::to_string(n).size()));
  std::set<std::string> ids;
  std::set<std::vector<double>> points;
  std::set<std::uint64_t> seeds;
  std::map<std::vector<int>, std::size_t> per_cell;
  for (std::size_t i = 0; i < n; ++i) {
    const Scenario& s = plan.scenarios[i];
    EXPECT_EQ(s.id, fmt::format("S{:0{}}", i + 1, width));
    ids.insert(s.id);
    EXPECT_TRUE(points.insert(s.values).second) << s.id << " repeats a point";
    seeds.insert(s.seed);
    ASSERT_EQ(s.values.size(), odd.factors.size());
    EXPECT_TRUE(odd.admissible(s.values)) << s.id;
    EXPECT_EQ(s.cell, odd.cell_of(s.values)) << s.id;
    ++per_cell[s.cell];
    // Malfunctions: exactly the modes whose region holds here; transitions: theirs, first seen first.
    std::vector<std::string> modes, transitions;
    for (const auto& m : odd.malfunctions) {
      if (m.region && !m.region->holds(s.values)) continue;
      modes.push_back(m.id);
      for (const auto& t : m.transitions)
        if (std::find(transitions.begin(), transitions.end(), t) == transitions.end()) transitions.push_back(t);
    }
    EXPECT_EQ(s.malfunctions, modes) << s.id;
    EXPECT_EQ(s.transitions, transitions) << s.id;
  }
  EXPECT_EQ(ids.size(), n) << "ids are unique";
  EXPECT_EQ(seeds.size(), n) << "every scenario has its own seed";

  // Weights w = π(cell)·N/n(cell); they sum to N.
  const auto priors = cell_priors(odd);
  double sum = 0.0;
  for (const Scenario& s : plan.scenarios) {
    sum += s.weight;
    EXPECT_GE(s.weight, 0.0);
    const auto it = priors.find(s.cell);
    EXPECT_NE(it, priors.end()) << s.id << " lies in a cell the relevant-cell search did not find";
    if (it == priors.end()) continue;
    const double expected = it->second * static_cast<double>(n) / static_cast<double>(per_cell[s.cell]);
    EXPECT_NEAR(s.weight, expected, 1e-9 * std::max(1.0, expected)) << s.id;
  }
  EXPECT_NEAR(sum, static_cast<double>(n), 1e-9 * static_cast<double>(n));

  // Steps: the five steps in order; each scenario names its step and the counts agree.
  const std::vector<std::string> step_names{"boundary", "covering_array", "malfunction", "cell_fill", "top_up"};
  ASSERT_EQ(plan.steps.size(), step_names.size());
  std::size_t total_added = 0;
  std::size_t at = 0;
  for (std::size_t k = 0; k < step_names.size(); ++k) {
    EXPECT_EQ(plan.steps[k].name, step_names[k]);
    total_added += plan.steps[k].added;
    for (std::size_t j = 0; j < plan.steps[k].added && at < n; ++j, ++at)
      EXPECT_EQ(plan.scenarios[at].step, step_names[k]) << plan.scenarios[at].id;
  }
  EXPECT_EQ(total_added, n);

  // Tracked cells reach their sample size when the targets are met.
  const auto cells = relevant_cells(odd);
  EXPECT_EQ(plan.relevant_cells, cells.size());
  const auto tracked = std::count_if(cells.begin(), cells.end(), [](const RelevantCell& c) { return c.tracked; });
  EXPECT_EQ(plan.tracked_cells, static_cast<std::size_t>(tracked));
  if (plan.targets_met) {
    EXPECT_TRUE(plan.shortfalls.empty());
    for (const auto& c : cells) {
      if (c.tracked) {
        EXPECT_GE(per_cell[c.levels], plan.tests_per_tracked_cell) << cell_key(c.levels);
      }
      EXPECT_GE(per_cell[c.levels], static_cast<std::size_t>(odd.n_c)) << cell_key(c.levels);
    }
  }

  // Boundary targets: hit exactly by some scenario, or declared infeasible.
  for (const auto& t : boundary_targets(odd)) {
    const bool hit = std::any_of(plan.scenarios.begin(), plan.scenarios.end(),
                                 [&](const Scenario& s) { return s.values[t.factor] == t.value; });
    if (hit) continue;
    const bool listed = std::any_of(plan.infeasible.begin(), plan.infeasible.end(), [&](const std::string& s) {
      return s.find(odd.factors[t.factor].name) != std::string::npos;
    });
    EXPECT_TRUE(listed) << odd.factors[t.factor].name << " = " << t.value << " neither hit nor listed infeasible";
  }
  expect_shortfalls_are_real(odd, plan);
}

inline bool same_scenarios(const Plan& a, const Plan& b) {
  if (a.scenarios.size() != b.scenarios.size()) return false;
  for (std::size_t i = 0; i < a.scenarios.size(); ++i) {
    const Scenario& x = a.scenarios[i];
    const Scenario& y = b.scenarios[i];
    if (x.id != y.id || x.step != y.step || x.values != y.values || x.cell != y.cell || x.seed != y.seed ||
        x.weight != y.weight || x.malfunctions != y.malfunctions)
      return false;
  }
  return true;
}

// ---- a random ODD, as YAML text (so that the loader is exercised too) ---------------------------

struct RandomOddText {
  std::string yaml;
  int strength = 2;
};

inline RandomOddText random_odd(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  const auto integer = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  const auto chance = [&](double p) { return uniform(0.0, 1.0) < p; };
  const auto round1 = [](double v) { return std::round(v * 10.0) / 10.0; };

  struct Info {
    std::string name;
    double lo = 0.0;
    double hi = 1.0;  // numeric span, for normalised predicates
    bool multi = true;
    bool influential = true;
  };
  std::vector<Info> infos;
  std::string y = fmt::format("name: random {}\nseed: {}\nfactors:\n", seed, seed * 7 + 1);
  const int nf = integer(2, 5);
  bool have_constant = false;
  for (int i = 0; i < nf; ++i) {
    Info info;
    info.name = fmt::format("f{}", i);
    y += fmt::format("  - name: {}\n", info.name);
    int kind = integer(0, 9);  // 0-4 continuous, 5-6 integer, 7-8 categorical, 9 constant
    if (i < 2 && kind == 9) kind = 0;
    if (kind == 9 && have_constant) kind = 1;
    int levels = 1;
    if (kind <= 4) {
      levels = integer(2, 4);
      std::vector<double> edges{round1(uniform(-10.0, 10.0))};
      for (int k = 0; k < levels; ++k) edges.push_back(round1(edges.back() + uniform(0.5, 20.0)));
      y += "    bins: [";
      for (std::size_t k = 0; k < edges.size(); ++k) y += fmt::format("{}{:g}", k ? ", " : "", edges[k]);
      y += "]\n";
      if (chance(0.3)) y += fmt::format("    kinks: [{:g}]\n", round1(0.5 * (edges[0] + edges[1])) + 0.05);
      info.lo = edges.front();
      info.hi = edges.back();
    } else if (kind <= 6) {
      levels = integer(2, 3);
      std::vector<int> edges{integer(-5, 5)};
      for (int k = 0; k < levels; ++k) edges.push_back(edges.back() + integer(1, 4));
      y += "    type: integer\n    bins: [";
      for (std::size_t k = 0; k < edges.size(); ++k) y += fmt::format("{}{}", k ? ", " : "", edges[k]);
      y += "]\n";
      info.lo = edges.front();
      info.hi = edges.back();
    } else if (kind <= 8) {
      levels = integer(2, 4);
      y += "    type: categorical\n    classes: [";
      for (int k = 0; k < levels; ++k) y += fmt::format("{}c{}", k ? ", " : "", k);
      y += "]\n";
      info.lo = 0.0;
      info.hi = levels - 1.0;
      if (chance(0.5)) {
        // Numbers in a shuffled order, so that a class's number is not its index.
        std::vector<double> values;
        for (int k = 0; k < levels; ++k) values.push_back(0.5 * k + 1.0);
        std::shuffle(values.begin(), values.end(), rng);
        y += "    values: [";
        for (int k = 0; k < levels; ++k) y += fmt::format("{}{:g}", k ? ", " : "", values[static_cast<std::size_t>(k)]);
        y += "]\n";
        info.lo = 1.0;
        info.hi = 0.5 * (levels - 1) + 1.0;
      }
    } else {
      have_constant = true;
      const double v = round1(uniform(0.0, 5.0));
      y += fmt::format("    type: constant\n    value: {:g}\n", v);
      info.lo = v;
      info.hi = v + 1.0;
      info.multi = false;
      info.influential = false;
    }
    if (kind != 9 && chance(0.4)) {
      std::vector<double> p(static_cast<std::size_t>(levels));
      double total = 0.0;
      for (auto& x : p) total += (x = uniform(0.05, 1.0));
      if (levels >= 3 && chance(0.2)) {
        total -= p[1];
        p[1] = 0.0;  // a level never met in practice
      }
      y += "    prior: [";
      for (std::size_t k = 0; k < p.size(); ++k) y += fmt::format("{}{:.17g}", k ? ", " : "", p[k] / total);
      y += "]\n";
    }
    if (kind != 9 && i >= 2 && chance(0.2)) {
      y += "    influential: false\n";
      info.influential = false;
    }
    infos.push_back(info);
  }
  const auto norm = [&](std::size_t i) {
    return fmt::format("({} - ({:g})) / {:g}", infos[i].name, infos[i].lo, infos[i].hi - infos[i].lo);
  };
  std::vector<std::size_t> numeric;  // factors with more than one level
  for (std::size_t i = 0; i < infos.size(); ++i)
    if (infos[i].multi) numeric.push_back(i);
  std::shuffle(numeric.begin(), numeric.end(), rng);

  if (chance(0.5))
    y += fmt::format("relevance: \"{} + {} <= {:.2f}\"\n", norm(numeric[0]), norm(numeric[1]), uniform(0.6, 1.6));
  if (numeric.size() >= 3 && chance(0.4))
    y += fmt::format("constraints:\n  - \"{} >= {:.2f}\"\n", norm(numeric[2]), uniform(0.0, 0.3));
  if (chance(0.4)) y += fmt::format("tracked: \"{} < 0.5\"\n", norm(numeric[0]));

  const int modes = integer(1, 3);
  const std::vector<std::string> pool{"S1 -a-> S2", "S2 -b-> S3", "S3 -c-> S4", "S2 -d-> S1"};
  y += "malfunctions:\n";
  for (int m = 0; m < modes; ++m) {
    y += fmt::format("  - id: M{}\n", m + 1);
    const std::size_t a = numeric[static_cast<std::size_t>(integer(0, static_cast<int>(numeric.size()) - 1))];
    const std::size_t b = numeric[static_cast<std::size_t>(integer(0, static_cast<int>(numeric.size()) - 1))];
    const int shape = integer(0, 3);
    if (shape == 1) y += fmt::format("    region: \"{} < {:.2f}\"\n", norm(a), uniform(0.3, 0.9));
    if (shape == 2) y += fmt::format("    region: \"{} > {:.2f} || {} < 0.2\"\n", norm(a), uniform(0.2, 0.7), norm(b));
    if (shape == 3) y += fmt::format("    region: \"{} >= 0.5 && {} <= 0.6\"\n", norm(a), norm(b));
    y += fmt::format("    hazards: [H{}, H{}]\n", integer(1, 4), integer(1, 4));
    y += fmt::format("    transitions: [\"{}\", \"{}\"]\n", pool[static_cast<std::size_t>(integer(0, 3))],
                     pool[static_cast<std::size_t>(integer(0, 3))]);
  }
  std::size_t q = 0;
  for (const auto& info : infos) q += info.multi && info.influential ? 1 : 0;
  RandomOddText out;
  out.strength = q >= 3 && chance(0.4) ? 3 : 2;
  y += fmt::format("coverage: {{strength: {}, n_c: {}, n_m: {}, epsilon: {:.2f}, delta: {:.2f}, budget: {}}}\n",
                   out.strength, integer(1, 2), integer(1, 3), uniform(0.3, 0.45), uniform(0.02, 0.2),
                   integer(150, 500));
  out.yaml = y;
  return out;
}

}  // namespace emrm::scenario::test_support
