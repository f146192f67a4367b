#pragma once

// Private to the figure code: what the figures of figures.cpp and the maps of map_figures.cpp
// share (a figure's files, a cell's value along an axis).

#include <filesystem>
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

/// A factor of a grid's cells, as a figure's axis or a map's slice.
enum class Axis { kSpeed, kTtc, kMu, kPassage, kTruckSpeed };

/// The cell's ego speed (km/h), TTC (s), μ, passage width (m) or truck speed (km/h).
[[nodiscard]] double value_of(const campaign::CellRecord& r, Axis a);

/// The distinct values of `a` over `cells`, ascending (values within kSameValue are one).
[[nodiscard]] std::vector<double> distinct_values(const std::vector<campaign::CellRecord>& cells, Axis a);

/// A feasible cell in region O or R.
[[nodiscard]] bool is_o_or_r(const campaign::CellRecord& c);
/// An O/R cell whose region rests on a failed search only: no avoidance found, none proven impossible.
[[nodiscard]] bool is_undecided(const campaign::CellRecord& c);

}  // namespace emrm::report::detail
