#pragma once

// Private to the figure code: what the figures of figures.cpp and the maps (map_panels.hpp)
// share (a figure's files, a cell's value along an axis).

#include <filesystem>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/figures.hpp"

namespace emrm::report::detail {

// Grid values such as 0.25 + 7·0.06 are a few ulps off their decimal; they are one value.
inline constexpr double kSameValue = 1e-9;

/// Gives the figure its paths in `dir` (NAME.png, .svg, .csv) and writes its CSV.
void write_csv(Figure& figure, const std::filesystem::path& dir, const core::Row& header,
               const std::vector<core::Row>& rows);

/// A factor of a grid's cells (its place in the scenario's factor table), as a figure's axis or a
/// map's slice; kSpeed, kTtc and kFriction are the method's factors, which every scenario has.
struct Axis {
  std::size_t index = 0;
  static const Axis kSpeed, kTtc, kFriction;
  friend bool operator==(Axis, Axis) = default;
};
inline constexpr Axis Axis::kSpeed{sim::kEgoSpeedFactor};
inline constexpr Axis Axis::kTtc{sim::kTtcFactor};
inline constexpr Axis Axis::kFriction{sim::kFrictionFactor};

/// The cell's value of the factor.
[[nodiscard]] double value_of(const campaign::CellRecord& r, Axis a);
/// The factor's entry in `factors`.
[[nodiscard]] inline const sim::Factor& factor_of(const sim::FactorTable& factors, Axis a) { return factors[a.index]; }
/// The key columns a figure's CSV names the factors of a cell by, in table order.
[[nodiscard]] core::Row factor_columns(const sim::FactorTable& factors);

/// The distinct values of `a` over `cells`, ascending (values within kSameValue are one).
[[nodiscard]] std::vector<double> distinct_values(const std::vector<campaign::CellRecord>& cells, Axis a);

/// A figure's file stem: letters, digits, '.', '-' and '_' kept, anything else '_'.
[[nodiscard]] std::string file_stem(std::string_view text);

/// The stems of one set of figures: `unique(stem)` returns the stem, or stem_2, stem_3, … when
/// it is taken (two slices whose names map to the same file).
class StemSet {
 public:
  [[nodiscard]] std::string unique(std::string stem);

 private:
  std::set<std::string> taken_;
};

/// A strategy's label in figure keys: the registry's ("emergency stop"), else its name with spaces.
[[nodiscard]] std::string strategy_label(std::string_view strategy);
/// A strategy's colour "#rrggbb": the registry's, else one of a few extra colours by its place
/// among the unregistered ones of `strategies`.
[[nodiscard]] std::string strategy_colour(std::string_view strategy, const std::vector<std::string>& strategies);

/// A one-panel map of `cells` (one grid's, sharing every factor but speed and TTC) with curves
/// drawn over it: the boundary figures (boundary_figures.cpp).
struct OverlaidMap {
  sim::FactorTable factors;  ///< the scenario's
  std::string grid;
  std::vector<campaign::CellRecord> cells;
  std::string held;                 ///< what the cells share, as the heading says it: "μ = 0.5, passage 3 m"
  std::string title;                ///< the figure's heading (shown literally)
  std::string data;                 ///< the curves' datablocks
  std::vector<std::string> layers;  ///< their plot items, drawn over the cells in this order
  std::vector<std::string> key;     ///< their key entries, after the regions'
};

/// What the caption of an overlaid map says of its cells.
struct MapCaption {
  std::string extent;    ///< "5 speeds × 6 TTCs, μ = 0.5"
  std::string shares;    ///< "G a %, Y b %, O c %, R d % of N feasible[, k undecided]"
  std::string evidence;  ///< a sentence on the undecided and certified O/R cells, or ""
};

/// Draws `map` into figure.png and figure.svg: speed × TTC, each cell in the mitigability map's
/// region colour (undecided O/R cells crossed), then map.layers on top; no closed-form stop
/// boundary of its own. Throws as render_png_and_svg, and emrm::Error for a feasible cell whose
/// region is not G, Y, O or R.
MapCaption draw_overlaid_map(const Figure& figure, const OverlaidMap& map);

/// A feasible cell in region O or R.
[[nodiscard]] bool is_o_or_r(const campaign::CellRecord& c);
/// An O/R cell whose region rests on a failed search only: no avoidance found, none proven impossible.
[[nodiscard]] bool is_undecided(const campaign::CellRecord& c);

}  // namespace emrm::report::detail
