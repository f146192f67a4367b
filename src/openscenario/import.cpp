// What `emrm import` makes of a scenario: the scene, the sweeps of a parameter distribution and
// --factor-range, and the campaign over them (import.hpp).

#include "emrm/openscenario/import.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "emrm/core/error.hpp"
#include "emrm/openscenario/parameters.hpp"
#include "emrm/openscenario/reader.hpp"

namespace emrm::openscenario {
namespace {

// The parameters a distribution varies, in the order it names them; each once, declared by the
// scenario and numeric (InputError at the distribution element otherwise).
std::vector<std::string> varied_parameters(const ParameterDistribution& d, const std::vector<Parameter>& declared) {
  std::vector<std::string> out;
  const auto take = [&](const std::string& name, const SourceLocation& where, bool once) {
    const auto p = std::find_if(declared.begin(), declared.end(), [&](const Parameter& q) { return q.name == name; });
    if (p == declared.end())
      throw InputError(where, fmt::format("the distribution varies '{}', which {} does not declare", name,
                                          d.scenario_file.filename().string()));
    if (!numeric(p->type))
      throw InputError(where, fmt::format("the distribution varies '{}', a {} parameter: emrm sweeps numeric "
                                          "parameters only (double, int, unsignedInt, unsignedShort)",
                                          name, type_name(p->type)));
    const bool seen = std::find(out.begin(), out.end(), name) != out.end();
    if (seen && once) throw InputError(where, fmt::format("the distribution varies '{}' twice", name));
    if (!seen) out.push_back(name);
  };
  for (const SingleParameterValues& s : d.single) take(s.parameter, s.where, true);
  for (const ValueSets& m : d.multi) {
    std::set<std::string> in_these;  // a parameter may be in every set of one distribution
    for (const auto& set : m.sets)
      for (const auto& [name, value] : set)
        if (in_these.insert(name).second) take(name, m.where, true);
  }
  return out;
}

// A parameter's value as its factor's: the ego's speed parameter in km/h as speed_kph.
struct FactorOf {
  std::string key;
  double scale = 1.0;
};

FactorOf factor_of(const sim::SceneConfig& scene, const std::string& parameter) {
  if (parameter == scene.openscenario.speed_parameter) return {"speed_kph", sim::kKphPerMps};
  return {parameter, 1.0};
}

// What is wrong with a sweep of the scene's factors, if anything: a factor it does not have, a
// value the factor does not accept.
std::optional<std::string> sweep_problem(const sim::FactorTable& table, const FactorSweep& sweep) {
  const auto i = table.find(sweep.factor);
  if (!i) return fmt::format("the scene has no factor '{}' (it has {})", sweep.factor, table.key_list());
  const sim::Factor& f = table[*i];
  std::vector<double> ends;
  if (const auto* range = std::get_if<ValueRange>(&sweep.values))
    ends = {range->lower, range->upper};
  else
    ends = std::get<std::vector<double>>(sweep.values);
  for (const double v : ends)
    if (!f.accepts(v)) return f.refusal(v);
  return std::nullopt;
}

// The distribution's sweeps and value sets, as the scene's factors.
void add_distribution(const ParameterDistribution& d, const sim::FactorTable& table, ImportedScenario& out) {
  for (const SingleParameterValues& s : d.single) {
    const FactorOf f = factor_of(out.scene, s.parameter);
    FactorSweep sweep{f.key, std::vector<double>{}, s.where.str()};
    if (const auto* range = std::get_if<ValueRange>(&s.values)) {
      sweep.values = ValueRange{range->lower * f.scale, range->upper * f.scale, range->step * f.scale};
    } else {
      std::vector<double> values;
      for (const std::string& text : std::get<std::vector<std::string>>(s.values)) {
        const auto v = parse_number(text);
        if (!v) throw InputError(s.where, fmt::format("{}: expected a number, got '{}'", s.parameter, text));
        values.push_back(*v * f.scale);
      }
      sweep.values = std::move(values);
    }
    if (const auto problem = sweep_problem(table, sweep)) throw InputError(s.where, *problem);
    out.sweeps.push_back(std::move(sweep));
  }
  out.value_sets = {{}};
  for (const ValueSets& m : d.multi) {
    if (out.value_sets.size() * std::max<std::size_t>(m.sets.size(), 1) > kMaxValueSets)
      throw InputError(m.where, fmt::format("the distributions' value sets make more than {} concrete scenarios "
                                            "(each a grid of the campaign)",
                                            kMaxValueSets));
    std::vector<std::map<std::string, double>> product;
    for (const auto& before : out.value_sets)
      for (const auto& set : m.sets) {
        auto joined = before;
        for (const auto& [parameter, text] : set) {
          const FactorOf f = factor_of(out.scene, parameter);
          const auto v = parse_number(text);
          if (!v) throw InputError(m.where, fmt::format("{}: expected a number, got '{}'", parameter, text));
          const sim::Factor& factor = table[*table.find(f.key)];
          if (!factor.accepts(*v * f.scale)) throw InputError(m.where, factor.refusal(*v * f.scale));
          joined[f.key] = *v * f.scale;
        }
        product.push_back(std::move(joined));
      }
    out.value_sets = std::move(product);
  }
  if (out.value_sets.size() == 1 && out.value_sets.front().empty()) out.value_sets.clear();
}

// A number for the campaign, to 12 digits: without the noise of a conversion (0.3 m/s * 3.6).
std::string number_text(double v) { return fmt::format("{:.12g}", v); }

std::string sweep_text(const std::variant<ValueRange, std::vector<double>>& values) {
  if (const auto* r = std::get_if<ValueRange>(&values))
    return fmt::format("{{from: {}, to: {}, step: {}}}", number_text(r->lower), number_text(r->upper),
                       number_text(r->step));
  std::vector<std::string> texts;
  for (const double v : std::get<std::vector<double>>(values)) texts.push_back(number_text(v));
  return fmt::format("[{}]", fmt::join(texts, ", "));
}

}  // namespace

FactorSweep parse_factor_range(const std::string& text) {
  const auto fail = [&] {
    return UsageError(
        fmt::format("--factor-range: expected KEY=FROM:TO:STEP (ttc_s=0.1:2:0.1), with FROM <= TO and STEP > 0, got "
                    "'{}'",
                    text));
  };
  const std::size_t eq = text.find('=');
  if (eq == 0 || eq == std::string::npos) throw fail();
  std::vector<double> parts;
  std::string_view rest = std::string_view(text).substr(eq + 1);
  for (std::size_t colon = rest.find(':');; colon = rest.find(':')) {
    const auto v = parse_number(rest.substr(0, colon));
    if (!v) throw fail();
    parts.push_back(*v);
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  if (parts.size() != 3 || parts[0] > parts[1] || !(parts[2] > 0.0)) throw fail();
  return {text.substr(0, eq), ValueRange{parts[0], parts[1], parts[2]}, "--factor-range " + text};
}

ImportedScenario import_scenario(const std::filesystem::path& file, const ImportChoices& choices,
                                 const std::vector<FactorSweep>& ranges) {
  const std::filesystem::path path = std::filesystem::absolute(file).lexically_normal();
  ImportedScenario out;
  if (!is_parameter_distribution(path)) {
    out.scene = scene_of(path, choices);
  } else {
    const ParameterDistribution d = load_parameter_distribution(path);
    if (std::error_code ec; !std::filesystem::is_regular_file(d.scenario_file, ec))
      throw InputError(d.scenario_where, fmt::format("ScenarioFile: expected the scenario the distribution varies, but "
                                                     "'{}' is not a file",
                                                     d.scenario_file.string()));
    const std::vector<std::string> varied = varied_parameters(d, declared_parameters(d.scenario_file));
    ImportChoices chosen = choices;
    if (chosen.factors.empty()) {
      chosen.factors = varied;
    } else {
      for (const std::string& name : varied)
        if (std::find(chosen.factors.begin(), chosen.factors.end(), name) == chosen.factors.end())
          chosen.factors.push_back(name);  // scene_of leaves out the ego's speed parameter
    }
    out.scene = scene_of(d.scenario_file, chosen);
    add_distribution(d, sim::scenario_factors(out.scene), out);
  }
  const sim::FactorTable table = sim::scenario_factors(out.scene);
  for (const FactorSweep& range : ranges) {
    if (const auto problem = sweep_problem(table, range))
      throw UsageError(fmt::format("{}: {}", range.source, *problem));
    std::erase_if(out.sweeps, [&](const FactorSweep& s) { return s.factor == range.factor; });
    for (auto& set : out.value_sets) set.erase(range.factor);
    out.sweeps.push_back(range);
  }
  std::stable_sort(out.sweeps.begin(), out.sweeps.end(), [&](const FactorSweep& a, const FactorSweep& b) {
    return *table.find(a.factor) < *table.find(b.factor);
  });
  return out;
}

std::string campaign_yaml(const ImportedScenario& imported, const std::string& scene_ref) {
  const sim::FactorTable table = sim::scenario_factors(imported.scene);
  // The axes in the factor table's order, as the sweeps are; the TTC (the method's second factor)
  // over the default range when nothing sweeps it.
  const std::string& ttc_key = table[sim::kTtcFactor].key;
  const bool ttc_swept = std::any_of(imported.sweeps.begin(), imported.sweeps.end(),
                                     [&](const FactorSweep& s) { return s.factor == ttc_key; });
  std::string axes;
  for (std::size_t i = 0; i < table.size(); ++i) {
    for (const FactorSweep& s : imported.sweeps)
      if (s.factor == table[i].key) axes += fmt::format("    {}: {}\n", s.factor, sweep_text(s.values));
    if (i == sim::kTtcFactor && !ttc_swept)
      axes += fmt::format("    {}: {}  # emrm import's default\n", ttc_key, sweep_text(kDefaultTtcSweep));
  }
  std::string grids;
  if (imported.value_sets.empty()) {
    grids = "  - name: imported\n" + axes;
  } else {
    for (std::size_t i = 0; i < imported.value_sets.size(); ++i) {
      grids += fmt::format("  - name: set{}\n", i + 1);
      for (const auto& [key, value] : imported.value_sets[i])
        grids += fmt::format("    {}: {}\n", key, number_text(value));
      grids += axes;
    }
  }
  std::vector<std::string> held;
  for (const sim::Factor& f : table)
    if (std::none_of(imported.sweeps.begin(), imported.sweeps.end(),
                     [&](const FactorSweep& s) { return s.factor == f.key; }) &&
        f.key != ttc_key)
      held.push_back(fmt::format("{} {}", f.key, f.value_text(f.default_value)));
  return fmt::format(
      "# A campaign over the scene {} written by `emrm import` (docs/import.md). Factors not swept take\n"
      "# their defaults: {}.\n"
      "# Run:  emrm sweep THIS_FILE -o out/imported\n\n"
      "scene: {}\nseed: 1\n\ngrids:\n{}",
      imported.scene.name, held.empty() ? std::string("none") : fmt::format("{}", fmt::join(held, ", ")), scene_ref,
      grids);
}

}  // namespace emrm::openscenario
