#include "emrm/scenario/odd.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include "emrm/core/domain.hpp"
#include "emrm/core/text.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/safety/load.hpp"
#include "emrm/scenario/plan.hpp"

namespace emrm::scenario {

// ---- OddFactor ---------------------------------------------------------------------------------

int OddFactor::levels() const noexcept {
  switch (type) {
    case FactorType::kContinuous:
    case FactorType::kInteger:
      return static_cast<int>(edges.size()) - 1;
    case FactorType::kCategorical:
      return static_cast<int>(classes.size());
    case FactorType::kConstant:
      return 1;
  }
  return 1;
}

int OddFactor::level_of(double value) const noexcept {
  if (is_numeric_range()) {
    // Bin k is [edges[k], edges[k+1]); the last bin is closed.
    const auto it = std::upper_bound(edges.begin(), edges.end(), value);
    const auto k = static_cast<int>(it - edges.begin()) - 1;
    return std::clamp(k, 0, levels() - 1);
  }
  if (type == FactorType::kCategorical) {
    int best = 0;
    for (int k = 1; k < levels(); ++k)
      if (std::abs(class_values[static_cast<std::size_t>(k)] - value) <
          std::abs(class_values[static_cast<std::size_t>(best)] - value))
        best = k;
    return best;
  }
  return 0;
}

std::string OddFactor::level_label(int level) const {
  const auto k = static_cast<std::size_t>(level);
  switch (type) {
    case FactorType::kContinuous:
    case FactorType::kInteger:
      return fmt::format("[{:g}, {:g}{}", edges[k], edges[k + 1], level + 1 == levels() ? "]" : ")");
    case FactorType::kCategorical:
      return classes[k];
    case FactorType::kConstant:
      return fmt::format("{:g}", edges.empty() ? nominal : edges.front());
  }
  return {};
}

double OddFactor::lower(int level) const noexcept {
  const auto k = static_cast<std::size_t>(level);
  if (is_numeric_range()) return edges[k];
  if (type == FactorType::kCategorical) return class_values[k];
  return nominal;
}

double OddFactor::upper(int level) const noexcept {
  const auto k = static_cast<std::size_t>(level);
  if (is_numeric_range()) return edges[k + 1];
  if (type == FactorType::kCategorical) return class_values[k];
  return nominal;
}

double OddFactor::domain_min() const noexcept {
  if (is_numeric_range()) return edges.front();
  if (type == FactorType::kCategorical) return *std::min_element(class_values.begin(), class_values.end());
  return nominal;
}

double OddFactor::domain_max() const noexcept {
  if (is_numeric_range()) return edges.back();
  if (type == FactorType::kCategorical) return *std::max_element(class_values.begin(), class_values.end());
  return nominal;
}

// ---- Odd ---------------------------------------------------------------------------------------

std::vector<std::string> Odd::factor_names() const {
  std::vector<std::string> names;
  names.reserve(factors.size());
  for (const auto& f : factors) names.push_back(f.name);
  return names;
}

std::optional<std::size_t> Odd::factor_index(std::string_view factor_name) const {
  for (std::size_t i = 0; i < factors.size(); ++i)
    if (factors[i].name == factor_name) return i;
  return std::nullopt;
}

std::vector<std::size_t> Odd::influential() const {
  std::vector<std::size_t> q;
  for (std::size_t i = 0; i < factors.size(); ++i)
    if (factors[i].influential && factors[i].levels() > 1) q.push_back(i);
  return q;
}

std::vector<int> Odd::cell_of(std::span<const double> values) const {
  std::vector<int> cell(factors.size());
  for (std::size_t i = 0; i < factors.size(); ++i) cell[i] = factors[i].level_of(values[i]);
  return cell;
}

bool Odd::admissible(std::span<const double> values) const {
  if (relevance && !relevance->holds(values)) return false;
  return std::all_of(constraints.begin(), constraints.end(), [&](const auto& c) { return c.holds(values); });
}

double Odd::cell_count() const noexcept {
  double n = 1.0;
  for (const auto& f : factors) n *= f.levels();
  return n;
}

// ---- loading -----------------------------------------------------------------------------------

namespace {

namespace fs = std::filesystem;

// A YAML node kept as it is, read later by hand (a factor's nominal: a number or a class name).
struct RawNode {
  std::optional<core::YamlNode> node;
};

}  // namespace
}  // namespace emrm::scenario

template <>
struct emrm::core::YamlCodec<emrm::scenario::RawNode> {
  static void read(const YamlNode& n, emrm::scenario::RawNode& v) { v.node = n; }
  static YAML::Node write(const emrm::scenario::RawNode& v) { return v.node ? v.node->raw() : YAML::Node(); }
};

namespace emrm::scenario {
namespace {

// A factor as written; checked and turned into an OddFactor by make_factor.
struct FactorYaml {
  std::string name;
  std::string unit;
  std::string description;
  FactorType type = FactorType::kContinuous;
  std::optional<std::vector<double>> bins;
  std::vector<double> kinks;
  std::optional<std::vector<std::string>> classes;
  std::optional<std::vector<double>> values;
  std::optional<double> value;
  std::optional<std::vector<double>> prior;
  std::optional<bool> influential;
  RawNode nominal;
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("name", name);
    a.optional("unit", unit);
    a.optional("description", description);
    a.optional("type", type);
    a.optional("bins", bins);
    a.optional("kinks", kinks);
    a.optional("classes", classes);
    a.optional("values", values);
    a.optional("value", value);
    a.optional("prior", prior);
    a.optional("influential", influential);
    a.optional("nominal", nominal);
  }
};

struct MalfunctionYaml {
  std::string id;
  std::string description;
  std::optional<std::string> region;
  std::vector<std::string> hazards;
  std::vector<std::string> transitions;
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("id", id);
    a.optional("description", description);
    a.optional("region", region);
    a.optional("hazards", hazards);
    a.optional("transitions", transitions);
  }
};

struct CoverageYaml {
  int strength = 2;
  int n_c = 1;
  int n_m = 3;
  double epsilon = 0.25;
  double delta = 0.05;
  long long budget = 1000;
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.optional("strength", strength);
    a.optional("n_c", n_c);
    a.optional("n_m", n_m);
    a.optional("epsilon", epsilon);
    a.optional("delta", delta);
    a.optional("budget", budget);
  }
};

struct AcceptanceYaml {
  std::string strategy = "emrm";
  Acceptance outcome = Acceptance::kAvoided;

  template <class A>
  void serialize(A& a) {
    a.optional("strategy", strategy);
    a.optional("outcome", outcome);
  }
};

bool valid_identifier(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// The node of a field of `map` (for messages), or the map itself.
core::YamlNode field(const core::YamlNode& map, std::string_view key) {
  auto child = map.find(key);
  return child ? *child : map;
}

void check_increasing(const std::vector<double>& edges, const core::YamlNode& node, std::string_view what) {
  for (std::size_t k = 1; k < edges.size(); ++k)
    if (!(edges[k] > edges[k - 1]))
      node.fail(fmt::format("{} must increase strictly, but {:g} follows {:g} (position {}); bins may not "
                            "overlap or be unsorted",
                            what, edges[k], edges[k - 1], k + 1));
}

std::vector<double> default_prior(const OddFactor& f) {
  const int n = f.levels();
  std::vector<double> prior(static_cast<std::size_t>(n), 1.0 / n);
  if (f.type == FactorType::kContinuous) {
    const double width = f.edges.back() - f.edges.front();
    for (int k = 0; k < n; ++k) prior[static_cast<std::size_t>(k)] = (f.upper(k) - f.lower(k)) / width;
  } else if (f.type == FactorType::kInteger) {
    // Integers per bin: [lo, hi) holds hi − lo of them, the closed last bin one more.
    const double count = f.edges.back() - f.edges.front() + 1.0;
    for (int k = 0; k < n; ++k)
      prior[static_cast<std::size_t>(k)] = (f.upper(k) - f.lower(k) + (k + 1 == n ? 1.0 : 0.0)) / count;
  }
  return prior;
}

// The centre of the most probable level (the first on ties).
double default_nominal(const OddFactor& f) {
  const auto best = static_cast<int>(std::max_element(f.prior.begin(), f.prior.end()) - f.prior.begin());
  if (f.type == FactorType::kInteger) return std::floor(0.5 * (f.lower(best) + f.upper(best)));
  return 0.5 * (f.lower(best) + f.upper(best));
}

OddFactor make_factor(const FactorYaml& y, const core::YamlNode& node) {
  OddFactor f;
  f.name = y.name;
  f.unit = y.unit;
  f.type = y.type;
  f.kinks = y.kinks;
  f.where = y.where;
  if (!valid_identifier(y.name))
    field(node, "name").fail(fmt::format(
        "factor name '{}' is not an identifier (letters, digits and _, starting with a letter)", y.name));
  const auto forbid = [&](bool present, std::string_view key, std::string_view type) {
    if (present) field(node, key).fail(fmt::format("'{}' does not apply to a {} factor", key, type));
  };
  switch (y.type) {
    case FactorType::kContinuous:
    case FactorType::kInteger: {
      const auto type = core::enum_name(y.type);
      forbid(y.classes.has_value(), "classes", type);
      forbid(y.values.has_value(), "values", type);
      forbid(y.value.has_value(), "value", type);
      if (!y.bins) node.fail(fmt::format("a {} factor needs 'bins': at least two increasing edges", type));
      f.edges = *y.bins;
      const auto bins_node = field(node, "bins");
      if (f.edges.size() < 2)
        bins_node.fail(fmt::format("'bins' needs at least two edges (one bin), got {}", f.edges.size()));
      check_increasing(f.edges, bins_node, "bin edges");
      if (y.type == FactorType::kInteger)
        for (double e : f.edges)
          if (e != std::round(e)) bins_node.fail(fmt::format("bin edges of an integer factor must be integers, got {:g}", e));
      for (double k : f.kinks)
        if (!(k > f.edges.front() && k < f.edges.back()))
          field(node, "kinks").fail(fmt::format("kink {:g} lies outside the open domain ({:g}, {:g})", k,
                                                f.edges.front(), f.edges.back()));
      break;
    }
    case FactorType::kCategorical: {
      forbid(y.bins.has_value(), "bins", "categorical");
      forbid(!y.kinks.empty(), "kinks", "categorical");
      forbid(y.value.has_value(), "value", "categorical");
      if (!y.classes || y.classes->empty()) node.fail("a categorical factor needs 'classes': a list of names");
      f.classes = *y.classes;
      std::set<std::string> seen;
      for (const auto& c : f.classes)
        if (!seen.insert(c).second) field(node, "classes").fail(fmt::format("duplicate class '{}'", c));
      if (y.values) {
        if (y.values->size() != f.classes.size())
          field(node, "values").fail(fmt::format("'values' has {} numbers for {} classes", y.values->size(),
                                                 f.classes.size()));
        f.class_values = *y.values;
        std::set<double> distinct(f.class_values.begin(), f.class_values.end());
        if (distinct.size() != f.class_values.size())
          field(node, "values").fail("the classes' values must differ");
      } else {
        f.class_values.resize(f.classes.size());
        std::iota(f.class_values.begin(), f.class_values.end(), 0.0);
      }
      break;
    }
    case FactorType::kConstant:
      forbid(y.bins.has_value(), "bins", "constant");
      forbid(!y.kinks.empty(), "kinks", "constant");
      forbid(y.classes.has_value(), "classes", "constant");
      forbid(y.values.has_value(), "values", "constant");
      forbid(y.prior.has_value(), "prior", "constant");
      if (!y.value) node.fail("a constant factor needs 'value'");
      f.nominal = *y.value;
      break;
  }
  if (y.prior) {
    const auto prior_node = field(node, "prior");
    if (static_cast<int>(y.prior->size()) != f.levels())
      prior_node.fail(fmt::format("'prior' has {} probabilities for {} levels", y.prior->size(), f.levels()));
    double sum = 0.0;
    for (double p : *y.prior) {
      if (p < 0.0) prior_node.fail(fmt::format("prior probabilities must be >= 0, got {:g}", p));
      sum += p;
    }
    if (std::abs(sum - 1.0) > 1e-6)
      prior_node.fail(fmt::format("prior does not normalise: its probabilities sum to {:.9g}, expected 1", sum));
    f.prior = *y.prior;
  } else {
    f.prior = default_prior(f);
  }
  f.influential = y.influential.value_or(f.levels() > 1);
  if (f.type != FactorType::kConstant) f.nominal = default_nominal(f);
  if (y.nominal.node) {
    const core::YamlNode& n = *y.nominal.node;
    if (f.type == FactorType::kCategorical) {
      const std::string name = n.as_string();
      const auto it = std::find(f.classes.begin(), f.classes.end(), name);
      if (it == f.classes.end())
        n.fail(fmt::format("nominal '{}' is not a class of '{}' ({})", name, f.name, core::join(f.classes, ", ")));
      f.nominal = f.class_values[static_cast<std::size_t>(it - f.classes.begin())];
    } else {
      f.nominal = core::scalar_number(n);
      if (f.type == FactorType::kInteger && f.nominal != std::round(f.nominal))
        n.fail(fmt::format("nominal of the integer factor '{}' must be a whole number, got {:g}", f.name, f.nominal));
      if (f.nominal < f.domain_min() || f.nominal > f.domain_max())
        n.fail(fmt::format("nominal {:g} lies outside the domain [{:g}, {:g}]", f.nominal, f.domain_min(),
                           f.domain_max()));
    }
  }
  return f;
}

std::vector<std::string> split_transitions(const std::vector<core::TransitionRef>& refs) {
  std::vector<std::string> out;
  for (const auto& t : refs) out.push_back(t.str());
  return out;
}

void add_unique(std::vector<std::string>& list, const std::string& item) {
  if (std::find(list.begin(), list.end(), item) == list.end()) list.push_back(item);
}

// The relevance predicate, then the constraints one by one: the first whose addition leaves no
// relevant cell is the culprit.
void check_satisfiable(const Odd& odd, const std::vector<core::YamlNode>& constraint_nodes,
                       const std::optional<core::YamlNode>& relevance_node) {
  if (!relevant_cells(odd).empty()) return;
  Odd partial = odd;
  partial.constraints.clear();
  if (relevant_cells(partial).empty())
    relevance_node->fail("no point of the domain satisfies the relevance predicate");
  for (std::size_t i = 0; i < odd.constraints.size(); ++i) {
    partial.constraints.push_back(odd.constraints[i]);
    if (relevant_cells(partial).empty())
      constraint_nodes[i].fail(
          "the constraints are unsatisfiable: with this one, no point of the domain satisfies the relevance "
          "predicate and every constraint");
  }
}

}  // namespace

std::vector<Malfunction> malfunctions_from(const safety::SafetyCase& sc, const std::vector<std::string>& factors) {
  std::vector<Malfunction> out;
  for (const auto& uca : sc.ucas) {
    Malfunction m;
    m.id = uca.id;
    m.description = uca.context;
    m.where = uca.where;
    if (uca.region_expression)
      m.region.emplace(uca.region_expression->text(), factors, uca.region_expression->where());
    for (const auto& h : uca.hazards) m.hazards.push_back(h.id);
    m.transitions = split_transitions(uca.fsm_transitions);
    out.push_back(std::move(m));
  }
  return out;
}

Odd parse_odd(const std::string& text, const std::string& file_name, const fs::path& base_dir,
              const std::optional<fs::path>& safety_override) {
  const core::YamlNode root = core::YamlNode::parse(text, file_name);
  if (!root.is_map()) root.fail("expected an ODD (a mapping with name, factors, coverage, ...), got " + root.describe());
  Odd odd;
  odd.file = file_name;
  std::optional<core::YamlNode> factors_node, relevance_node, tracked_node, malfunctions_node, coverage_node,
      acceptance_node, baselines_node, safety_node, hazards_node;
  std::vector<core::YamlNode> constraint_nodes;
  for (const auto& [key, value] : root.entries()) {
    const std::string k = key.as_string();
    if (k == "name") {
      odd.name = value.as_string();
    } else if (k == "description") {
      odd.description = value.as_string();
    } else if (k == "seed") {
      const long long seed = value.as_int();
      if (seed < 0) value.fail(fmt::format("seed must be >= 0, got {}", seed));
      odd.seed = static_cast<std::uint64_t>(seed);
    } else if (k == "factors") {
      factors_node = value;
    } else if (k == "relevance") {
      relevance_node = value;
    } else if (k == "constraints") {
      constraint_nodes = value.elements();
    } else if (k == "tracked") {
      tracked_node = value;
    } else if (k == "malfunctions") {
      malfunctions_node = value;
    } else if (k == "hazards") {
      hazards_node = value;
    } else if (k == "coverage") {
      coverage_node = value;
    } else if (k == "acceptance") {
      acceptance_node = value;
    } else if (k == "baselines") {
      baselines_node = value;
    } else if (k == "safety") {
      safety_node = value;
    } else if (k == "scene") {
      fs::path p = value.as_string();
      if (p.is_relative()) p = base_dir / p;
      if (!fs::is_regular_file(p)) value.fail("scene file '" + p.string() + "' does not exist");
      odd.scene_file = p;
    } else if (k == "strategies") {
      for (const auto& s : value.elements()) odd.strategies.push_back(s.as_string());
    } else {
      key.fail("unknown field '" + k +
               "'; expected name, description, seed, safety, scene, strategies, factors, relevance, constraints, "
               "tracked, malfunctions, hazards, coverage, acceptance or baselines");
    }
  }

  // Factors.
  if (!factors_node) root.fail("missing field 'factors'");
  for (const auto& element : factors_node->elements()) {
    FactorYaml y;
    core::read_yaml(element, y);
    OddFactor f = make_factor(y, element);
    if (odd.factor_index(f.name)) field(element, "name").fail(fmt::format("duplicate factor '{}'", f.name));
    odd.factors.push_back(std::move(f));
  }
  if (odd.factors.empty()) factors_node->fail("an ODD needs at least one factor");
  const std::vector<std::string> names = odd.factor_names();

  // Predicates.
  if (relevance_node) odd.relevance = core::Expression(*relevance_node, names);
  for (const auto& c : constraint_nodes) odd.constraints.push_back(core::Expression(c, names));
  if (tracked_node) odd.tracked = core::Expression(*tracked_node, names);

  // Coverage targets.
  if (coverage_node) {
    CoverageYaml c;
    core::read_yaml(*coverage_node, c);
    const auto q = odd.influential();
    if (c.strength != 2 && c.strength != 3)
      field(*coverage_node, "strength").fail(fmt::format("strength must be 2 or 3, got {}", c.strength));
    if (static_cast<std::size_t>(c.strength) > q.size()) {
      std::vector<std::string> qn;
      for (auto i : q) qn.push_back(odd.factors[i].name);
      field(*coverage_node, "strength")
          .fail(fmt::format("strength {} is larger than the number of influential factors with more than one "
                            "level ({}: {})",
                            c.strength, q.size(), qn.empty() ? "none" : core::join(qn, ", ")));
    }
    if (c.n_c < 1) field(*coverage_node, "n_c").fail(fmt::format("n_c must be >= 1, got {}", c.n_c));
    if (c.n_m < 0) field(*coverage_node, "n_m").fail(fmt::format("n_m must be >= 0, got {}", c.n_m));
    if (!(c.epsilon > 0.0 && c.epsilon < 0.5))
      field(*coverage_node, "epsilon").fail(fmt::format("epsilon must lie in (0, 0.5), got {:g}", c.epsilon));
    if (!(c.delta > 0.0 && c.delta < 1.0))
      field(*coverage_node, "delta").fail(fmt::format("delta must lie in (0, 1), got {:g}", c.delta));
    if (c.budget < 1) field(*coverage_node, "budget").fail(fmt::format("budget must be >= 1, got {}", c.budget));
    odd.strength = c.strength;
    odd.n_c = c.n_c;
    odd.n_m = c.n_m;
    odd.epsilon = c.epsilon;
    odd.delta = c.delta;
    odd.budget = static_cast<std::size_t>(c.budget);
  } else if (odd.influential().size() < 2) {
    root.fail("the default strength 2 needs at least two influential factors with more than one level");
  }

  if (acceptance_node) {
    AcceptanceYaml a;
    core::read_yaml(*acceptance_node, a);
    odd.acceptance_strategy = a.strategy;
    odd.acceptance = a.outcome;
  }

  // Malfunction modes: the safety case's UCAs, then the file's own list.
  std::optional<fs::path> safety_path = safety_override;
  if (!safety_path && safety_node) {
    fs::path p = safety_node->as_string();
    if (p.is_relative()) p = base_dir / p;
    if (!fs::is_regular_file(p)) safety_node->fail("safety file '" + p.string() + "' does not exist");
    safety_path = p;
  }
  if (safety_path) {
    if (!fs::is_regular_file(*safety_path))
      throw UsageError(fmt::format("--safety: '{}' does not exist", safety_path->string()));
    const safety::SafetyCase sc = safety::load_safety_case(*safety_path);
    odd.safety_file = *safety_path;
    odd.malfunctions = malfunctions_from(sc, names);
    for (const auto& h : sc.hazards) odd.hazards.push_back(h.id);
    if (sc.fsm) {
      const fsm::Generator g = fsm::load_generator(safety_path->parent_path() / *sc.fsm);
      for (const auto& t : g.transitions())
        odd.fsm_transitions.push_back(t.str());
    }
  }
  if (malfunctions_node) {
    for (const auto& element : malfunctions_node->elements()) {
      MalfunctionYaml y;
      core::read_yaml(element, y);
      for (const auto& m : odd.malfunctions)
        if (m.id == y.id) field(element, "id").fail(fmt::format("duplicate malfunction mode '{}'", y.id));
      Malfunction m;
      m.id = y.id;
      m.description = y.description;
      m.where = y.where;
      if (y.region) m.region = core::Expression(field(element, "region"), names);
      m.hazards = y.hazards;
      m.transitions = y.transitions;
      odd.malfunctions.push_back(std::move(m));
    }
  }
  if (hazards_node)
    for (const auto& h : hazards_node->elements()) add_unique(odd.hazards, h.as_string());
  for (const auto& m : odd.malfunctions)
    for (const auto& h : m.hazards) add_unique(odd.hazards, h);

  // Manual baseline grid.
  if (baselines_node) {
    for (const auto& [key, value] : baselines_node->entries()) {
      if (key.as_string() != "manual") key.fail("unknown baseline '" + key.as_string() + "'; expected manual");
      for (const auto& [fkey, fvalue] : value.entries()) {
        const auto i = odd.factor_index(fkey.as_string());
        if (!i)
          fkey.fail(fmt::format("unknown factor '{}'; expected one of {}", fkey.as_string(), core::join(names, ", ")));
        odd.manual_grid.emplace_back(*i, core::expand_values(fvalue));
      }
    }
  }

  if (odd.cell_count() > 200000)
    factors_node->fail(fmt::format("the factors' levels make {:.0f} cells, more than 200000; use fewer bins",
                                   odd.cell_count()));
  check_satisfiable(odd, constraint_nodes, relevance_node);
  return odd;
}

Odd load_odd(const fs::path& path, const std::optional<fs::path>& safety_override) {
  const std::string text = core::read_input_file(path);
  return parse_odd(text, path.string(), path.parent_path(), safety_override);
}

}  // namespace emrm::scenario
