#pragma once

// A campaign (docs/campaign.md): a scene, a seed, the strategies to compare and
// named grids of scenario cells over the ODD factors. Loading expands every grid into its cells,
// in a fixed order, so that a cell is named by (grid, index) everywhere: in the store, the
// exports, the shards and the tables.

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/core/error.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::campaign {

/// One named grid, expanded: the cartesian product of its factors (in the order of the scene's
/// factor table, sim::scenario_factors; the last varies fastest) or its explicit `cells:` list, in
/// file order.
struct GridSpec {
  std::string name;
  std::vector<sim::CellInput> cells;
  std::vector<std::uint64_t> seeds;  ///< one per cell (a planned scenario's own); empty: cell_seed()
  bool keep_trees = false;           ///< store paths and planner trees of every strategy (trajectory figure)
  SourceLocation where;              ///< the grid's mapping in the campaign file
  /// A product grid's levels per factor (in the factor table's order), in expansion order; empty for
  /// a grid that lists its cells.
  std::vector<std::vector<double>> levels;
  /// `adaptive: true`: swept by the adaptive boundary search (docs/adaptive.md). Product grids only.
  bool adaptive = false;
};

/// The most cells a campaign may hold over all its grids, --force or not: each cell's inputs,
/// outcomes and exported rows are held in memory (a few hundred bytes a cell), and a campaign of this
/// size already takes days on a laptop. Larger domains are split into several campaigns.
inline constexpr std::size_t kMaxCampaignCells = 5'000'000;

struct Campaign {
  std::string file;                       ///< the campaign file
  std::optional<std::string> scene_file;  ///< as written (relative to the campaign file)
  sim::SceneConfig scene;                 ///< loaded scene (defaults if none)
  std::uint64_t seed = 1;
  std::vector<std::string> strategies = sim::strategy_names();
  std::vector<GridSpec> grids;
  std::size_t max_cells = 20000;  ///< per grid, unless --force; at most kMaxCampaignCells
  std::string text;               ///< the campaign file's text, kept in the results store
};

/// Checks a campaign, loaded or built in code: its scene (sim::validate), strategies that are
/// registered (sim::validate_strategy), listed once and not none, max_cells in [1,
/// kMaxCampaignCells], no more than kMaxCampaignCells cells over all grids (even with `force`), at least one
/// grid, and for every grid a name that is not empty and not another grid's, at least one cell,
/// every cell accepted by sim::validate_cell, a seed per cell or none, and — unless `force` — no
/// more than max_cells cells. The seed is unsigned: any value is valid. Throws core::ConfigError
/// (an InputError) naming the field path: "campaign: grids[1].cells[3]: grid 'g': mu must be ...".
void validate(const Campaign& campaign, bool force = false);

/// Loads and expands a campaign file, then validate(campaign, force). Throws InputError
/// (file:line:column) for malformed YAML, unknown fields or factors, a negative seed, empty or
/// reversed ranges, non-positive steps, levels < 1, a product grid of more than max_cells cells
/// (unless `force`) or taking the campaign past kMaxCampaignCells (checked before it is expanded), and what validate()
/// rejects, at the node it names: a cell of a product grid at the first factor value the simulator rejects on its own.
/// A missing or bad scene file is reported at the `scene:` entry or inside the scene file.
[[nodiscard]] Campaign load_campaign(const std::filesystem::path& path, bool force = false);

/// The folder of the campaign's scene file (the campaign file's when it names none): where its
/// profiles/ folder is.
[[nodiscard]] std::filesystem::path scene_folder(const Campaign& campaign);
/// Overlays an actuation profile (sim::apply_profile) on a loaded campaign's scene; a NAME is
/// looked up in the profiles/ folder beside the scene file (beside the campaign file when it names
/// none).
void apply_profile(Campaign& campaign, const std::string& profile);
/// As load_campaign, from text; a relative `scene:` is resolved against `base_dir`.
[[nodiscard]] Campaign parse_campaign(const std::string& text, const std::string& file_name,
                                      const std::filesystem::path& base_dir, bool force = false);

/// 16 hex digits identifying the effective configuration (scene, seed, strategies, every grid's
/// cells) and the emrm version: a results store only accepts more cells of the same hash.
[[nodiscard]] std::string config_hash(const Campaign& campaign);

/// The key of a cell: the grid name and the factor values (in the factor table's order) formatted with %.9g.
[[nodiscard]] std::string cell_key(const std::string& grid, const sim::CellInput& cell);
/// sim::derive_seed(campaign.seed, cell_key(grid, cell)): the same on every run, thread and shard.
[[nodiscard]] std::uint64_t cell_seed(const Campaign& campaign, const std::string& grid, const sim::CellInput& cell);
/// The seed cell `index` of `grid` is simulated with: the grid's own (a planned scenario's) when it
/// lists them, else the one above.
[[nodiscard]] std::uint64_t cell_seed(const Campaign& campaign, const GridSpec& grid, std::size_t index);

/// The row form of a simulated cell of `scene` (speeds in km/h; traces kept; paths and trees only
/// with `keep_trajectories`, simulated with trees kept). The scene's factor table is made only for
/// a cell with a certificate (its JSON names the cell's factors): most cells of a sweep have none.
[[nodiscard]] CellRecord to_record(const sim::SceneConfig& scene, const std::string& grid, std::int64_t index,
                                   std::uint64_t seed, const sim::CellResult& result, bool keep_trajectories = false);

/// Number of cells over all grids.
[[nodiscard]] std::size_t total_cells(const Campaign& campaign) noexcept;

}  // namespace emrm::campaign
