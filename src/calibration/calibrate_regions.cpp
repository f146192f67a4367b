// `emrm calibrate --regions`: fits actuation parameters to a grid's target region fractions
// (docs/actuation.md, "Calibrating to a map"). G is the stop's closed form, so a fit to G alone
// sweeps nothing; Y, O and R need the planners, so a fit to them simulates the grid's cells the
// stop cannot save, once per parameter vector tried.

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "emrm/calibration/calibrate.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "fit.hpp"

namespace emrm::calibration {
namespace {

constexpr std::array<std::string_view, 4> kRegions{"G", "Y", "O", "R"};

const campaign::GridSpec& grid_named(const campaign::Campaign& campaign, const RegionTarget& target) {
  std::vector<std::string> names;
  for (const auto& g : campaign.grids) {
    if (g.name == target.grid) return g;
    names.push_back(g.name);
  }
  throw InputError(target.grid_at, fmt::format("grid '{}' is not in the campaign {} (its grids: {})", target.grid,
                                               campaign.file, core::join(names, ", ")));
}

// The region fractions of a grid's feasible cells under one actuation: G from the closed form, and
// with `simulate` the others from the planners (cells the stop saves are not simulated). A family
// without the stop boundary (sim::stop_boundary_applies) has no closed form: every cell is simulated.
class RegionCounter {
 public:
  RegionCounter(const campaign::Campaign& campaign, const campaign::GridSpec& grid, int threads)
      : campaign_(campaign), grid_(grid), closed_form_(sim::stop_boundary_applies(campaign.scene)) {
    if (threads < 0) throw UsageError(fmt::format("--threads must be >= 0, got {}", threads));
    if (threads > 0) limit_.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    for (std::size_t i = 0; i < grid.cells.size(); ++i)
      if (sim::Scene(campaign.scene, grid.cells[i]).feasible()) feasible_.push_back(i);
  }

  [[nodiscard]] std::size_t feasible() const noexcept { return feasible_.size(); }
  [[nodiscard]] std::size_t sweeps() const noexcept { return sweeps_; }
  /// Whether G has the closed form (else percent() must simulate).
  [[nodiscard]] bool closed_form() const noexcept { return closed_form_; }

  /// Percent of the feasible cells in each region (only G without `simulate`).
  std::map<std::string, double> percent(const sim::ActuationConfig& a, bool simulate) {
    std::vector<std::size_t> rest;
    std::map<std::string, double> count{{"G", 0.0}};
    for (const std::size_t i : feasible_) {
      const sim::CellInput& c = grid_.cells[i];
      if (closed_form_ && sim::analytically_stoppable(c, a))
        count["G"] += 1.0;
      else
        rest.push_back(i);
    }
    if (simulate) {
      for (const auto r : kRegions) count.try_emplace(std::string(r), 0.0);
      for (const auto& region : regions(a, rest)) count[region] += 1.0;
    }
    for (auto& [name, n] : count) n *= 100.0 / static_cast<double>(feasible_.size());
    return count;
  }

 private:
  // The regions of `cells` simulated under `a`, in order (the same for any number of threads).
  std::vector<std::string> regions(const sim::ActuationConfig& a, const std::vector<std::size_t>& cells) {
    ++sweeps_;
    sim::SceneConfig scene = campaign_.scene;
    scene.actuation = a;
    std::vector<std::string> out(cells.size());
    tbb::parallel_for(std::size_t{0}, cells.size(), [&](std::size_t k) {
      const std::size_t i = cells[k];
      sim::CellOptions options;
      options.strategies = campaign_.strategies;
      options.seed = campaign::cell_seed(campaign_, grid_, i);
      out[k] = std::string(sim::region_name(sim::simulate_cell(scene, grid_.cells[i], options).region));
    });
    return out;
  }

  const campaign::Campaign& campaign_;
  const campaign::GridSpec& grid_;
  bool closed_form_;
  std::optional<tbb::global_control> limit_;
  std::vector<std::size_t> feasible_;
  std::size_t sweeps_ = 0;
};

std::vector<std::string> matched_regions(const RegionTarget& target, const std::vector<std::string>& match) {
  std::vector<std::string> given;
  for (const auto& [name, pct] : target.pct) given.push_back(name);
  if (match.empty()) return given;
  std::set<std::string> seen;
  for (const auto& m : match) {
    if (!target.pct.contains(m))
      throw UsageError(fmt::format("--match: '{}' is not a region fraction of {} (it gives: {})", m, target.file,
                                   core::join(given, ", ")));
    if (!seen.insert(m).second) throw UsageError(fmt::format("--match: '{}' is named twice", m));
  }
  return match;
}

}  // namespace

RegionTarget read_region_target(const std::filesystem::path& file) {
  const core::YamlNode root = core::YamlNode::load_file(file);
  if (!root.is_map()) root.fail("expected a mapping with grid and regions_pct (or paper_reference.yaml's fine_grid)");
  // paper_reference.yaml keeps its map under fine_grid; a file of one's own has it at the top.
  const std::optional<core::YamlNode> nested = root.find("fine_grid");
  const core::YamlNode node = nested ? *nested : root;
  if (!node.is_map()) node.fail(fmt::format("expected a mapping with grid and regions_pct, got {}", node.describe()));
  RegionTarget t;
  t.file = file.string();
  for (const auto& [key, value] : node.entries()) {
    const std::string k = key.as_string();
    if (k == "grid") {
      t.grid = value.as_string();
      t.grid_at = value.location();
    } else if (k == "regions_pct") {
      if (!value.is_map())
        value.fail(
            fmt::format("regions_pct: expected a mapping of G, Y, O, R to percentages, got {}", value.describe()));
      for (const auto& [region, pct] : value.entries()) {
        const std::string name = region.as_string();
        if (std::ranges::find(kRegions, name) == kRegions.end())
          region.fail(fmt::format("regions_pct: unknown region '{}'; expected G, Y, O or R", name));
        const double v = pct.as_double();
        if (v < 0.0 || v > 100.0)
          pct.fail(fmt::format("regions_pct.{}: expected a percentage in [0, 100], got {:g}", name, v));
        t.pct[name] = v;
      }
    } else if (!nested && k != "feasible_cells" && k != "source" && k != "description") {
      key.fail(fmt::format("unknown field '{}'; expected grid, regions_pct, feasible_cells, source or description", k));
    }
  }
  if (t.grid.empty()) node.fail("missing field 'grid' (the campaign grid the fractions are of)");
  if (t.pct.empty()) node.fail("missing field 'regions_pct' (at least one of G, Y, O, R)");
  if (t.pct.size() == kRegions.size()) {
    double sum = 0.0;
    for (const auto& [name, v] : t.pct) sum += v;
    if (std::abs(sum - 100.0) > 1.0)
      node.at("regions_pct")
          .fail(fmt::format("regions_pct: G + Y + O + R must be 100 % (±1 for rounding), got {:g}", sum));
  }
  return t;
}

RegionCalibration calibrate_regions(const campaign::Campaign& campaign, const RegionTarget& target,
                                    const std::vector<std::string>& match, const CalibrationRequest& request,
                                    int threads) {
  const campaign::GridSpec& grid = grid_named(campaign, target);
  const std::vector<std::string> matched = matched_regions(target, match);
  RegionCounter counter(campaign, grid, threads);
  const double n = static_cast<double>(counter.feasible());
  if (counter.feasible() == 0)
    throw InputError(target.grid_at, fmt::format("grid '{}' has no feasible cell to compare fractions on", grid.name));
  const bool simulate =
      !counter.closed_form() || std::ranges::any_of(matched, [](const std::string& m) { return m != "G"; });

  fit::Problem p;
  fit::add_fitted(p, request);
  const std::size_t dims = p.low.size();
  p.observations = matched.size();
  p.chi_square = true;
  p.piecewise_constant = true;
  // A sweep per evaluation is dear: a short global search, and interval ends to 0.5 % of the range.
  p.max_evaluations = simulate ? static_cast<int>(12 * dims + 6) : static_cast<int>(400 * dims);
  p.interval_tolerance = simulate ? 5e-3 : 1e-4;
  std::map<std::vector<double>, std::map<std::string, double>> seen;  // every evaluation, reused
  const auto fractions = [&](const std::vector<double>& x) -> const std::map<std::string, double>& {
    auto it = seen.find(x);
    if (it == seen.end()) it = seen.emplace(x, counter.percent(fit::with(request, x), simulate)).first;
    return it->second;
  };
  p.sse = [&](const std::vector<double>& x) {
    const auto& f = fractions(x);
    double chi2 = 0.0;
    for (const auto& m : matched) {
      // The binomial variance of a fraction measured on n cells (+1/n² so 0 % and 100 % keep a width).
      const double t = target.pct.at(m) / 100.0;
      const double variance = (t * (1.0 - t) + 1.0 / n) / n;
      const double d = f.at(m) / 100.0 - t;
      chi2 += d * d / variance;
    }
    return chi2;
  };

  RegionCalibration out;
  out.calibration = fit::solve(p, request, /*check_correlations=*/false);
  std::vector<double> best;
  for (const auto& name : request.fit) best.push_back(out.calibration.fitted.at(name).value);
  const auto& at_best = fractions(best);
  double sum = 0.0;
  for (const auto& m : matched) {
    out.target_pct[m] = target.pct.at(m);
    const double d = at_best.at(m) - target.pct.at(m);
    sum += d * d;
  }
  out.fitted_pct = at_best;
  out.calibration.residual_rms = std::sqrt(sum / static_cast<double>(matched.size()));
  if (request.fit.size() > matched.size())
    out.calibration.warnings.push_back(fmt::format(
        "{} parameters are fitted to {} region fraction(s): at most {} of them can be determined, the rest only in "
        "combination",
        request.fit.size(), matched.size(), matched.size()));
  out.grid = grid.name;
  out.feasible_cells = counter.feasible();
  out.sweeps = counter.sweeps();
  return out;
}

}  // namespace emrm::calibration
