#pragma once

// Adaptive boundary search (docs/adaptive.md): the region of every cell of a product grid from
// the simulations of a fraction of them. The search knows nothing of the simulator: it asks an
// Oracle whether a cell is feasible, whether the analytic stop boundary settles it, and, for the
// cells it chooses, what a simulation says. So it is tested on synthetic maps as well as real ones.
//
// The structure it uses: along the monotone axis (TTC, or friction when TTC has one level) the
// stop (G) and avoidance (G or Y) are monotone — a cell that can be avoided stays avoidable with
// more time or more grip — so each line of cells along it is settled by two thresholds and the
// O/R labels below them; where the truck is still moving, a line may also start with an early run
// (the car passing in front of the truck at the lowest TTCs: sooner is better there), settled by
// two more thresholds, where G and avoidance end; lines are inferred from the lines at the corners of boxes of the
// other factors when those corners agree, and boxes whose corners disagree are split in two along every factor.
// Whatever the simulations show against monotonicity is reported and resolved.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/scenario/statistics.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/stop_physics.hpp"

namespace emrm::campaign::adaptive {

/// The levels of a product grid's factors, in the order a grid expands them (the last varies
/// fastest), as written (not necessarily sorted); at most kMaxAxes factors.
struct Lattice {
  static constexpr std::size_t kMaxAxes = 5;
  std::vector<std::vector<double>> levels;
  /// The factor along which stopping and avoiding are monotone (more time is never worse): the TTC
  /// ...
  std::size_t ttc_axis = 1;
  /// ... or the friction, when the TTC takes one level.
  std::size_t friction_axis = 2;

  [[nodiscard]] std::size_t size() const noexcept;
  /// The cell's index in the grid's expansion order from its level indices.
  [[nodiscard]] std::size_t index(const std::array<std::size_t, kMaxAxes>& level) const noexcept;
};

/// What the oracle says of a cell's emergency stop without simulating it (sim/stop_physics.hpp).
using StopCall = sim::StopCall;

/// What the search asks about cells, named by their index in the grid's expansion order.
/// simulate() is called from several threads at once, never twice for one cell.
class Oracle {
 public:
  virtual ~Oracle() = default;
  [[nodiscard]] virtual bool feasible(std::size_t cell) const = 0;
  [[nodiscard]] virtual StopCall stop(std::size_t cell) const = 0;
  /// The cell's region (G, Y, O or R) by simulation.
  [[nodiscard]] virtual sim::Region simulate(std::size_t cell) = 0;
  /// Whether arriving sooner can help at this cell: a truck still on its way when the car gets
  /// there, which the car may pass in front of at the lowest TTCs (a moving truck). Then a line
  /// along TTC may start with a run of its own that avoids, below the cells that cannot.
  [[nodiscard]] virtual bool passes_early(std::size_t /*cell*/) const { return false; }
  /// Whether an unavoidable cell is R without a simulation: the crash of doing nothing is already
  /// graded the lowest a crash can be. The labels below a line's avoidance threshold are then not
  /// sampled where it says so.
  [[nodiscard]] virtual bool nothing_to_mitigate(std::size_t /*cell*/) const { return false; }
};

/// Options::brackets.
enum class Brackets : std::uint8_t { kAuto, kSearch, kPredict };
/// The names of the Brackets, in the enum's order (what `emrm sweep --brackets` and Python take).
inline constexpr std::array<std::string_view, 3> kBracketsNames{"auto", "search", "predict"};
/// "auto", "search" or "predict".
[[nodiscard]] std::string_view brackets_name(Brackets brackets) noexcept;
/// The Brackets of one of kBracketsNames; nothing for any other name.
[[nodiscard]] std::optional<Brackets> brackets_named(std::string_view name) noexcept;

struct Options {
  /// Lines searched per factor across the domain before any refinement (at least 2); 0: 4 for
  /// the thresholds when the lines vary in one factor, 3 when in more, and 2 for the labels.
  std::size_t initial_levels = 0;
  /// Along a line, the unavoidable cells are sampled every `stride` cells before the changes
  /// between samples are bisected (at least 1; 1 simulates every unavoidable cell).
  std::size_t stride = 4;
  /// Corners whose avoidance thresholds differ by at most this many levels still agree: the lines
  /// between them search their own threshold within that bracket (log2 of it in simulations).
  std::uint32_t bracket = 1;
  /// How a line between corners whose thresholds agree within the bracket finds its own avoidance
  /// threshold: by simulations within the bracket (exact), or the threshold predicted from the
  /// corners without one (off by a level where the prediction is; the verification sample measures
  /// it); auto: predicted when the lines vary in two factors or more (grids of three or more).
  Brackets brackets = Brackets::kAuto;
  /// With predicted brackets: corners whose avoidance thresholds differ by up to this many levels
  /// (at least 1) agree, and the lines between take the threshold they predict.
  std::uint32_t spread = 3;
  /// With predicted brackets: a line between corners whose early runs end within `spread` levels of
  /// one another below the stop's run takes the end they predict (its G part is still searched).
  bool predict_early = true;
  /// Inferred cells re-simulated at random at the end to measure the disagreement rate; none: 0.5 %
  /// of the feasible cells, at least 20 and at most 500 (never more than were inferred).
  std::optional<std::size_t> verify_sample;
  std::uint64_t seed = 1;    ///< of the verification sample
  double confidence = 0.95;  ///< of the disagreement rate's Wilson interval
};

/// How a cell's region was found.
enum class Method : std::uint8_t {
  kNone,       ///< infeasible: no region
  kSimulated,  ///< simulated
  kStop,       ///< inferred: G by the analytic stop boundary
  kLine,       ///< inferred along its line between simulated cells (monotone avoidance, equal O/R labels)
  kBox,        ///< inferred from the lines at the corners of a box whose corners agree
};
[[nodiscard]] std::string_view method_name(Method m) noexcept;  ///< "simulated" or "inferred"
[[nodiscard]] std::string_view basis_name(Method m) noexcept;   ///< "", "simulated", "stop", "line", "box"

struct Cell {
  sim::Region region = sim::Region::kInfeasible;
  Method method = Method::kNone;
  /// Simulated cells: what the search simulated it for (a Purpose).
  std::uint8_t purpose = 0;
  /// Inferred cells: the simulated cells that bound the inference (at most 16, sorted).
  std::vector<std::uint32_t> from;
};

/// A simulation that contradicted monotonicity along a line, resolved by simulating the line and
/// its neighbours in full.
struct Violation {
  std::uint32_t low_cell = 0;   ///< the cell further down the monotone axis…
  std::uint32_t high_cell = 0;  ///< …that did better than this one
  std::string what;             ///< "stop" or "avoidance"
};

/// What a simulation was for (the stages of the search, in order).
enum class Purpose : std::uint8_t {
  kThresholdCorners,   ///< a corner line's stop boundary, avoidance threshold and early run
  kThresholdBrackets,  ///< a line between agreeing corners, within their bracket
  kLabels,             ///< a corner line's O/R labels
  kLabelBrackets,      ///< a line between corners whose labels change alike: its own changes
  kViolations,         ///< after a contradiction: lines resolved in full, thresholds searched again
  kVerification,       ///< the random sample of inferred cells
};
inline constexpr std::size_t kPurposes = 6;
[[nodiscard]] std::string_view purpose_name(Purpose p) noexcept;  ///< "threshold_corners", …

struct Result {
  std::vector<Cell> cells;                             ///< one per cell of the lattice
  std::size_t feasible = 0;                            ///< M
  std::size_t simulated = 0;                           ///< N: every cell simulated, the verification sample included
  std::array<std::size_t, kPurposes> simulated_for{};  ///< N by Purpose (they sum to N)
  std::size_t rounds = 0;
  std::size_t lines = 0, lines_resolved = 0, lines_inferred = 0;
  std::size_t lines_fully_resolved = 0;  ///< after a violation
  std::vector<Violation> violations;
  /// Verification: inferred cells (not analytic) re-simulated, and how many disagreed.
  std::size_t verify_population = 0;  ///< inferred cells the sample was drawn from
  std::size_t verify_sampled = 0;
  std::vector<std::uint32_t> verify_disagreements;  ///< cells whose simulation differed
  scenario::Interval disagreement;                  ///< Wilson interval of the disagreement rate
};

/// Throws std::invalid_argument for initial_levels 1, stride 0 or spread 0.
void check(const Options& options);

/// Throws std::invalid_argument for a factor without levels, or options check() refuses.
[[nodiscard]] Result search(const Lattice& lattice, Oracle& oracle, const Options& options);

}  // namespace emrm::campaign::adaptive
