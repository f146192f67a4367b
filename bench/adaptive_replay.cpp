// emrm_adaptive_replay CAMPAIGN RESULTS_SQLITE [INITIAL_LEVELS STRIDE VERIFY BRACKET BRACKETS [GRID]]:
// replays the adaptive search on a grid already swept in full, with the stored regions as the
// simulator. Prints, per adaptive-capable grid, the simulations the search would need (and how many
// of them were strengthened searches, the dear ones) and the cells its map would get wrong: the
// figures docs/adaptive.md reports, measured without simulating anything. A seventh argument
// prints the simulations per line of speed by friction. EMRM_SPREAD=N sets Options::spread,
// EMRM_NOEARLY=1 turns Options::predict_early off and EMRM_NORULE=1 the "nothing to mitigate" rule;
// EMRM_VIOLATIONS=1 lists the violations, EMRM_BOTTOM=1 counts the strengthened simulations at the
// lowest TTC. A stored certificate without a margin (written before the certificate checked arrivals
// before the brakes act) counts as a strengthened simulation, and so does an inferred O or R cell
// of an adaptive store (replayed on one, the search may simulate cells the store only inferred).

#include <fmt/format.h>

#include <array>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <map>

#include "emrm/campaign/adaptive.hpp"
#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/sim/stop_physics.hpp"

namespace {

using namespace emrm;

class StoredOracle final : public campaign::adaptive::Oracle {
 public:
  StoredOracle(const campaign::Campaign& c, const campaign::GridSpec& grid, std::vector<sim::Region> truth)
      : campaign_(c), grid_(grid), truth_(std::move(truth)) {}
  [[nodiscard]] bool feasible(std::size_t cell) const override {
    return sim::Scene(campaign_.scene, grid_.cells[cell]).feasible();
  }
  [[nodiscard]] campaign::adaptive::StopCall stop(std::size_t cell) const override {
    return sim::stop_call(campaign_.scene, grid_.cells[cell]);
  }
  [[nodiscard]] bool passes_early(std::size_t cell) const override {
    return sim::may_pass_early(campaign_.scene, grid_.cells[cell]);
  }
  [[nodiscard]] bool nothing_to_mitigate(std::size_t cell) const override {
    return rule_ && sim::nothing_to_mitigate(campaign_.scene, grid_.cells[cell]);
  }
  [[nodiscard]] sim::Region simulate(std::size_t cell) override {
    if (truth_[cell] == sim::Region::kInfeasible) ++unknown;  // not in the store: a replay of part of a grid
    return truth_[cell];
  }
  std::atomic<std::size_t> unknown{0};
  bool rule_ = std::getenv("EMRM_NORULE") == nullptr;

 private:
  const campaign::Campaign& campaign_;
  const campaign::GridSpec& grid_;
  std::vector<sim::Region> truth_;
};

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 3) {
    std::fputs(
        "usage: emrm_adaptive_replay CAMPAIGN RESULTS_SQLITE "
        "[INITIAL_LEVELS STRIDE VERIFY BRACKET BRACKETS [GRID]]\n",
        stderr);
    return 2;
  }
  const campaign::Campaign c = campaign::load_campaign(argv[1], true);
  campaign::adaptive::Options options;
  if (argc > 3) options.initial_levels = std::strtoul(argv[3], nullptr, 10);
  if (argc > 4) options.stride = std::strtoul(argv[4], nullptr, 10);
  if (argc > 5) options.verify_sample = std::strtoul(argv[5], nullptr, 10);
  if (argc > 6) options.bracket = static_cast<std::uint32_t>(std::strtoul(argv[6], nullptr, 10));
  if (argc > 7) {
    const auto brackets = campaign::adaptive::brackets_named(argv[7]);
    if (!brackets) throw std::invalid_argument("expected auto, search or predict");
    options.brackets = *brackets;
  }
  if (const char* v = std::getenv("EMRM_SPREAD"))
    options.spread = static_cast<std::uint32_t>(std::strtoul(v, nullptr, 10));
  if (std::getenv("EMRM_NOEARLY")) options.predict_early = false;
  std::map<std::string, std::vector<sim::Region>> truth;
  std::map<std::string, std::vector<char>> dear;  // the cell's search was strengthened (about 1 s, not 0.02)
  for (const campaign::GridSpec& grid : c.grids) {
    truth[grid.name].assign(grid.cells.size(), sim::Region::kInfeasible);
    dear[grid.name].assign(grid.cells.size(), 0);
  }
  campaign::ResultStore::open_for_reading(argv[2]).for_each_cell([&](const campaign::CellRecord& r) {
    auto& regions = truth[r.grid];
    if (r.index >= 0 && static_cast<std::size_t>(r.index) < regions.size()) {
      regions[static_cast<std::size_t>(r.index)] = r.region;
      // A certificate without a margin (stores written before the certificate checked an arrival
      // before the brakes act) no longer certifies: the cell's search is strengthened now.
      const bool void_certificate = r.certificate.find("\"margin_m\":null") != std::string::npos;
      // An inferred O or R cell of an adaptive store, simulated by the replay, is taken to be dear
      // (no certificate known): the estimate errs high.
      const bool inferred_unavoidable =
          r.method != campaign::CellMethod::kSimulated && (r.region == sim::Region::kO || r.region == sim::Region::kR);
      dear[r.grid][static_cast<std::size_t>(r.index)] =
          r.strengthened || void_certificate || inferred_unavoidable ? 1 : 0;
    }
  });
  for (const campaign::GridSpec& grid : c.grids) {
    if (grid.levels.empty()) continue;
    StoredOracle oracle(c, grid, truth[grid.name]);
    const auto result = campaign::adaptive::search(campaign::adaptive::Lattice{.levels = grid.levels}, oracle, options);
    std::size_t differ = 0, g_wrong = 0, strengthened = 0;
    for (std::size_t i = 0; i < result.cells.size(); ++i) {
      if (result.cells[i].method == campaign::adaptive::Method::kNone) continue;
      strengthened += result.cells[i].method == campaign::adaptive::Method::kSimulated && dear[grid.name][i];
      const sim::Region t = truth[grid.name][i];
      differ += result.cells[i].region != t;
      g_wrong += (result.cells[i].region == sim::Region::kG) != (t == sim::Region::kG);
    }
    fmt::print(
        "{}: {} cells, {} feasible; simulated {} ({:.1f} %); differ {} ({:.2f} %); G wrong {}; "
        "violations {}; lines {} resolved {} inferred {} full {}; rounds {}; strengthened {}\n",
        grid.name, grid.cells.size(), result.feasible, result.simulated,
        100.0 * static_cast<double>(result.simulated) / static_cast<double>(result.feasible), differ,
        100.0 * static_cast<double>(differ) / static_cast<double>(result.feasible), g_wrong, result.violations.size(),
        result.lines, result.lines_resolved, result.lines_inferred, result.lines_fully_resolved, result.rounds,
        strengthened);
    if (std::getenv("EMRM_VIOLATIONS"))
      for (const auto& v : result.violations) {
        const auto lo = sim::TJunctionCell::of(grid.cells[v.low_cell]);
        const auto hi = sim::TJunctionCell::of(grid.cells[v.high_cell]);
        fmt::print("  violation {}: {} km/h TTC {} .. {} mu {} passage {} truck {} ({} / {})\n", v.what, lo.speed_kph,
                   lo.ttc_s, hi.ttc_s, lo.mu, lo.passage_m, lo.truck_speed_kph,
                   sim::region_name(truth[grid.name][v.low_cell]), sim::region_name(truth[grid.name][v.high_cell]));
        fmt::print("    simulated for {} / {}\n",
                   campaign::adaptive::purpose_name(
                       static_cast<campaign::adaptive::Purpose>(result.cells[v.low_cell].purpose)),
                   campaign::adaptive::purpose_name(
                       static_cast<campaign::adaptive::Purpose>(result.cells[v.high_cell].purpose)));
      }
    fmt::print("  cost estimate {:.0f} s (1.0 s a strengthened simulation, 0.12 s another); not in the store: {}\n",
               1.0 * static_cast<double>(strengthened) + 0.12 * static_cast<double>(result.simulated - strengthened),
               oracle.unknown.load());
    std::array<std::size_t, campaign::adaptive::kPurposes> dear_for{};
    for (std::size_t i = 0; i < result.cells.size(); ++i)
      if (result.cells[i].method == campaign::adaptive::Method::kSimulated && dear[grid.name][i])
        ++dear_for[result.cells[i].purpose];
    if (std::getenv("EMRM_BOTTOM")) {  // strengthened simulations at the lowest TTC, by purpose
      std::array<std::size_t, campaign::adaptive::kPurposes> bottom{};
      for (std::size_t i = 0; i < result.cells.size(); ++i)
        if (result.cells[i].method == campaign::adaptive::Method::kSimulated && dear[grid.name][i] &&
            grid.cells[i].time_to_collision_s() == grid.levels[1].front())
          ++bottom[result.cells[i].purpose];
      fmt::print("  strengthened at the lowest TTC:");
      for (std::size_t p = 0; p < campaign::adaptive::kPurposes; ++p)
        fmt::print(" {} {}", campaign::adaptive::purpose_name(static_cast<campaign::adaptive::Purpose>(p)), bottom[p]);
      fmt::print("\n");
    }
    fmt::print("  strengthened for:");
    for (std::size_t p = 0; p < campaign::adaptive::kPurposes; ++p)
      fmt::print(" {} {}", campaign::adaptive::purpose_name(static_cast<campaign::adaptive::Purpose>(p)), dear_for[p]);
    fmt::print("\n");
    fmt::print("  simulated for:");
    for (std::size_t p = 0; p < campaign::adaptive::kPurposes; ++p)
      fmt::print(" {} {}", campaign::adaptive::purpose_name(static_cast<campaign::adaptive::Purpose>(p)),
                 result.simulated_for[p]);
    fmt::print("\n");
    if (argc > 8) {  // simulations per line of speed (columns) by friction (rows), TTC being the line
      const auto& l = grid.levels;
      for (std::size_t m = 0; m < l[2].size(); ++m) {
        fmt::print("mu {:5.2f} ", l[2][m]);
        for (std::size_t v = 0; v < l[0].size(); ++v) {
          int n = 0;
          for (std::size_t t = 0; t < l[1].size(); ++t)
            n += result.cells[campaign::adaptive::Lattice{.levels = l}.index({v, t, m, 0, 0})].method ==
                 campaign::adaptive::Method::kSimulated;
          fmt::print("{:3d}", n);
        }
        fmt::print("\n");
      }
    }
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "emrm_adaptive_replay: %s\n", e.what());
  return 2;
}
