// Loading an ODD file (docs/odd-yaml.md): the YAML shape of its factors, malfunction modes,
// coverage targets and acceptance, read into an Odd whose parts are checked by the rules of
// odd_rules.hpp as soon as they are read, each failure reported at its node in the file.

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numeric>

#include "emrm/core/domain.hpp"
#include "emrm/core/text.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/safety/load.hpp"
#include "emrm/scenario/odd.hpp"
#include "odd_rules.hpp"

namespace emrm::scenario {
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
  RawNode value;  // a number, or a level's name (LevelLookup)
  std::optional<std::vector<double>> prior;
  std::optional<bool> influential;
  RawNode nominal;
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    EMRM_REQUIRED_FIELD(a, name);
    EMRM_FIELD(a, unit);
    EMRM_FIELD(a, description);
    EMRM_FIELD(a, type);
    EMRM_FIELD(a, bins);
    EMRM_FIELD(a, kinks);
    EMRM_FIELD(a, classes);
    EMRM_FIELD(a, values);
    EMRM_FIELD(a, value);
    EMRM_FIELD(a, prior);
    EMRM_FIELD(a, influential);
    EMRM_FIELD(a, nominal);
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
    EMRM_REQUIRED_FIELD(a, id);
    EMRM_FIELD(a, description);
    EMRM_FIELD(a, region);
    EMRM_FIELD(a, hazards);
    EMRM_FIELD(a, transitions);
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
    EMRM_FIELD(a, strength);
    EMRM_FIELD(a, n_c);
    EMRM_FIELD(a, n_m);
    EMRM_FIELD(a, epsilon);
    EMRM_FIELD(a, delta);
    EMRM_FIELD(a, budget);
  }
};

struct AcceptanceYaml {
  std::string strategy;  // empty = the registered chooser
  Acceptance outcome = Acceptance::kAvoided;

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, strategy);
    EMRM_FIELD(a, outcome);
  }
};

// The node of a field of `map` (for messages), or the map itself.
core::YamlNode field(const core::YamlNode& map, std::string_view key) {
  auto child = map.find(key);
  return child ? *child : map;
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

// Runs rules of odd_rules.hpp and reports a failure at the node its path names below `root`.
template <class Rules>
void check_at(const core::YamlNode& root, Rules&& rules) {
  core::Validator v("odd");
  try {
    rules(v);
  } catch (const core::ConfigError& e) {
    core::fail_at(root, e, /*with_path=*/false);
  }
}

// The same for rules of the element `index` of the list `list` ("factors", "malfunctions").
template <class Rules>
void check_at(const core::YamlNode& root, std::string_view list, std::size_t index, Rules&& rules) {
  check_at(root, [&](core::Validator& v) {
    const core::Validator::Scope in_list(v, list);
    const core::Validator::Scope at(v, index);
    rules(v);
  });
}

// Where each value of a factor's domain was written: its bin edges, class numbers (else names) or
// constant value.
std::vector<SourceLocation> value_locations(const core::YamlNode& node) {
  for (const char* key : {"bins", "values", "classes"})
    if (const auto list = node.find(key); list && list->is_sequence()) {
      std::vector<SourceLocation> out;
      for (const auto& e : list->elements()) out.push_back(e.location());
      return out;
    }
  if (const auto value = node.find("value")) return {value->location()};
  return {};
}

// A factor as an OddFactor: first the keys its type takes and needs, then, at factors[index], its
// domain, its prior and its nominal value, each checked before the next is derived from it.
// A constant's value: a number, or with a lookup the name of a level of the scene's categorical
// factor of the same name (its index).
double constant_value(const core::YamlNode& n, const std::string& factor, const std::optional<fs::path>& scene_file,
                      const LevelLookup& levels) {
  const std::string text = n.is_scalar() ? n.as_string() : std::string();
  if (text.empty() || std::isalpha(static_cast<unsigned char>(text.front())) == 0) return core::scalar_number(n);
  const std::vector<std::string> names = levels ? levels(scene_file, factor) : std::vector<std::string>{};
  const auto it = std::find(names.begin(), names.end(), text);
  if (it != names.end()) return static_cast<double>(it - names.begin());
  if (names.empty())
    n.fail(fmt::format(
        "value '{}': expected a number{}", text,
        levels ? fmt::format(" (a level's name needs a categorical factor '{}' of the scene's family)", factor)
               : std::string()));
  n.fail(fmt::format("value '{}': expected one of the levels {} of the scene's family", text, core::join(names, ", ")));
}

OddFactor make_factor(const FactorYaml& y, const core::YamlNode& node, const core::YamlNode& root, std::size_t index,
                      const std::optional<fs::path>& scene_file, const LevelLookup& levels) {
  OddFactor f;
  f.name = y.name;
  f.unit = y.unit;
  f.type = y.type;
  f.kinks = y.kinks;
  f.where = y.where;
  f.unit_where = field(node, "unit").location();
  f.value_where = value_locations(node);
  const auto forbid = [&](bool present, std::string_view key, std::string_view type) {
    if (present) field(node, key).fail(fmt::format("'{}' does not apply to a {} factor", key, type));
  };
  switch (y.type) {
    case FactorType::kContinuous:
    case FactorType::kInteger: {
      const auto type = core::enum_name(y.type);
      forbid(y.classes.has_value(), "classes", type);
      forbid(y.values.has_value(), "values", type);
      forbid(y.value.node.has_value(), "value", type);
      if (!y.bins) node.fail(fmt::format("a {} factor needs 'bins': at least two increasing edges", type));
      f.edges = *y.bins;
      break;
    }
    case FactorType::kCategorical:
      forbid(y.bins.has_value(), "bins", "categorical");
      forbid(!y.kinks.empty(), "kinks", "categorical");
      forbid(y.value.node.has_value(), "value", "categorical");
      if (!y.classes) node.fail("a categorical factor needs 'classes': a list of names");
      f.classes = *y.classes;
      if (y.values) {
        f.class_values = *y.values;
      } else {
        f.class_values.resize(f.classes.size());
        std::iota(f.class_values.begin(), f.class_values.end(), 0.0);
      }
      break;
    case FactorType::kConstant:
      forbid(y.bins.has_value(), "bins", "constant");
      forbid(!y.kinks.empty(), "kinks", "constant");
      forbid(y.classes.has_value(), "classes", "constant");
      forbid(y.values.has_value(), "values", "constant");
      forbid(y.prior.has_value(), "prior", "constant");
      if (!y.value.node) node.fail("a constant factor needs 'value'");
      f.nominal = constant_value(*y.value.node, y.name, scene_file, levels);
      break;
  }
  const auto check = [&](auto&& rules) { check_at(root, "factors", index, rules); };
  check([&](core::Validator& v) { detail::check_factor_domain(v, f); });
  if (y.prior) {
    f.prior = *y.prior;
    check([&](core::Validator& v) { detail::check_factor_prior(v, f); });
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
      check([&](core::Validator& v) { detail::check_factor_nominal(v, f); });
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

}  // namespace

std::vector<Malfunction> malfunctions_from(const safety::SafetyCase& sc, const std::vector<std::string>& factors) {
  std::vector<Malfunction> out;
  for (const auto& uca : sc.ucas) {
    Malfunction m;
    m.id = uca.id;
    m.description = uca.context;
    m.where = uca.where;
    if (uca.region_expression) m.region.emplace(uca.region_expression->text(), factors, uca.region_expression->where());
    for (const auto& h : uca.hazards) m.hazards.push_back(h.id);
    m.transitions = split_transitions(uca.fsm_transitions);
    out.push_back(std::move(m));
  }
  return out;
}

Odd parse_odd(const std::string& text, const std::string& file_name, const fs::path& base_dir,
              const std::optional<fs::path>& safety_override, const LevelLookup& levels) {
  const core::YamlNode root = core::YamlNode::parse(text, file_name);
  if (!root.is_map())
    root.fail("expected an ODD (a mapping with name, factors, coverage, ...), got " + root.describe());
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
      for (const auto& s : value.elements()) {
        odd.strategies.push_back(s.as_string());
        odd.strategies_where.push_back(s.location());
      }
    } else {
      key.fail("unknown field '" + k +
               "'; expected name, description, seed, safety, scene, strategies, factors, relevance, constraints, "
               "tracked, malfunctions, hazards, coverage, acceptance or baselines");
    }
  }

  // Factors.
  if (!factors_node) root.fail("missing field 'factors'");
  const auto factor_elements = factors_node->elements();
  for (std::size_t i = 0; i < factor_elements.size(); ++i) {
    FactorYaml y;
    core::read_yaml(factor_elements[i], y);
    odd.factors.push_back(make_factor(y, factor_elements[i], root, i, odd.scene_file, levels));
    check_at(root, "factors", i, [&](core::Validator& v) { detail::check_factor_unique(v, odd, i); });
  }
  check_at(root, [&](core::Validator& v) { detail::check_factor_count(v, odd); });
  const std::vector<std::string> names = odd.factor_names();

  // Predicates.
  if (relevance_node) odd.relevance = core::Expression(*relevance_node, names);
  for (const auto& c : constraint_nodes) odd.constraints.push_back(core::Expression(c, names));
  if (tracked_node) odd.tracked = core::Expression(*tracked_node, names);

  // Coverage targets.
  if (coverage_node) {
    CoverageYaml c;
    core::read_yaml(*coverage_node, c);
    if (c.budget < 0) field(*coverage_node, "budget").fail(detail::budget_message(c.budget));  // no size_t holds it
    odd.strength = c.strength;
    odd.n_c = c.n_c;
    odd.n_m = c.n_m;
    odd.epsilon = c.epsilon;
    odd.delta = c.delta;
    odd.budget = static_cast<std::size_t>(c.budget);
    check_at(root, [&](core::Validator& v) { detail::check_coverage(v, odd); });
  } else if (odd.influential().size() < 2) {
    root.fail("the default strength 2 needs at least two influential factors with more than one level");
  }

  if (acceptance_node) {
    AcceptanceYaml a;
    core::read_yaml(*acceptance_node, a);
    odd.acceptance_strategy = a.strategy;
    odd.acceptance = a.outcome;
    const auto strategy = acceptance_node->is_map() ? acceptance_node->find("strategy") : std::nullopt;
    odd.acceptance_where = strategy ? strategy->location() : acceptance_node->location();
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
      for (const auto& t : g.transitions()) odd.fsm_transitions.push_back(t.str());
    }
  }
  if (malfunctions_node) {
    const auto elements = malfunctions_node->elements();
    for (std::size_t j = 0; j < elements.size(); ++j) {
      MalfunctionYaml y;
      core::read_yaml(elements[j], y);
      Malfunction& m = odd.malfunctions.emplace_back();
      m.id = y.id;
      m.description = y.description;
      m.where = y.where;
      m.hazards = y.hazards;
      m.transitions = y.transitions;
      check_at(root, "malfunctions", j,
               [&](core::Validator& v) { detail::check_malfunction(v, odd, odd.malfunctions.size() - 1); });
      if (y.region) odd.malfunctions.back().region = core::Expression(field(elements[j], "region"), names);
    }
  }
  if (hazards_node)
    for (const auto& h : hazards_node->elements()) add_unique(odd.hazards, h.as_string());
  // With a safety case its hazards are all there are: a UCA naming another one is a finding, not a
  // hazard to cover.
  if (!odd.safety_file)
    for (const auto& m : odd.malfunctions)
      for (const auto& h : m.hazards) add_unique(odd.hazards, h);

  // Manual baseline grid.
  if (baselines_node) {
    double points = 1.0;
    for (const auto& [key, value] : baselines_node->entries()) {
      if (key.as_string() != "manual") key.fail("unknown baseline '" + key.as_string() + "'; expected manual");
      for (const auto& [fkey, fvalue] : value.entries()) {
        const auto i = odd.factor_index(fkey.as_string());
        if (!i)
          fkey.fail(fmt::format("unknown factor '{}'; expected one of {}", fkey.as_string(), core::join(names, ", ")));
        odd.manual_grid.emplace_back(*i, core::expand_values(fvalue));
        points *= static_cast<double>(odd.manual_grid.back().second.size());
        if (points > static_cast<double>(kMaxManualGridPoints))
          fvalue.fail(fmt::format("the manual grid has {:.0f} points, more than the {} it may have; use fewer values",
                                  points, kMaxManualGridPoints));
      }
    }
  }

  check_at(root, [&](core::Validator& v) {
    detail::check_domain_size(v, odd);
    detail::check_satisfiable(v, odd);
  });
  return odd;
}

Odd load_odd(const fs::path& path, const std::optional<fs::path>& safety_override, const LevelLookup& levels) {
  const std::string text = core::read_input_file(path);
  return parse_odd(text, path.string(), path.parent_path(), safety_override, levels);
}

}  // namespace emrm::scenario
