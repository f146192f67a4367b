// The map: monotonicity checked, every cell given its region and its grounds, the verification sample.

#include <numeric>
#include <random>

#include "adaptive_search.hpp"

namespace emrm::campaign::adaptive::detail {

namespace {

constexpr std::size_t kMaxFrom = 16;  // the most simulated cells an inferred cell names as its grounds

}  // namespace

// Every simulated cell against the thresholds; the first contradiction, if any.
std::optional<Violation> Search::check(const Line& line) const {
  for (std::size_t i = 0; i < line.cells.size(); ++i) {
    const std::uint32_t cell = line.cells[i];
    const bool stops = oracle_.stop(cell) == StopCall::kStops;
    if (!is_simulated(cell) && !stops) continue;
    const Region r = stops && !is_simulated(cell) ? Region::kG : result_.cells[cell].region;
    const bool g = i < line.t_eg || i >= line.t_g;
    const bool a = i < line.t_e || i >= line.t_a;
    if (r == Region::kG && !g) return Violation{cell, line.cells[std::min(line.t_g, line.cells.size() - 1)], "stop"};
    if (r != Region::kG && g) return Violation{line.cells[i < line.t_eg ? 0 : line.t_g], cell, "stop"};
    if (avoidable(r) && !a) return Violation{cell, line.cells[line.t_a > 0 ? line.t_a - 1 : 0], "avoidance"};
    if (!avoidable(r) && a) return Violation{line.cells[i < line.t_e ? 0 : line.t_a], cell, "avoidance"};
  }
  return std::nullopt;
}

// After a contradiction: every cell the analytic stop run does not settle is simulated, and the
// thresholds and labels are read off the simulations.
void Search::resolve_fully(std::size_t id) {
  Line& line = lines_[id];
  line.full = true;
  line.thresholds_searched = line.thresholds_known = line.labels_sampled = line.labels_known = true;
  const std::size_t top = analytic_top(line);
  simulate_all({line.cells.begin(), line.cells.begin() + static_cast<long>(top)}, Purpose::kViolations);
  const auto region = [&](std::size_t i) { return result_.cells[line.cells[i]].region; };
  line.t_g = top;
  while (line.t_g > 0 && region(line.t_g - 1) == Region::kG) --line.t_g;
  line.early_searched = true;
  line.t_e = line.t_eg = 0;
  if (may_pass_early(line)) {
    while (line.t_e < line.t_g && avoidable(region(line.t_e))) ++line.t_e;
    while (line.t_eg < line.t_e && region(line.t_eg) == Region::kG) ++line.t_eg;
  }
  line.t_a = line.t_g;
  while (line.t_a > line.t_e && avoidable(region(line.t_a - 1))) --line.t_a;
  if (line.t_e > 0 && line.t_a == line.t_e)
    line.t_e = line.t_a = line.t_g;  // no cell below the stop's run cannot avoid
  line.labels.assign(line.t_a, Region::kR);
  for (std::size_t i = line.t_e; i < line.t_a; ++i) line.labels[i] = region(i);
}

// Simulations against the thresholds and labels of every line; a line that breaks monotonicity
// is simulated in full with its neighbours (theirs too, if they break it), until none does.
void Search::resolve_violations() {
  std::vector<char> queued(lines_.size(), 0);
  std::vector<std::size_t> todo;
  const auto scan = [&](const std::vector<std::size_t>& ids) {
    std::vector<std::size_t> next;
    for (std::size_t id : ids) {
      Line& line = lines_[id];
      if (line.violated) continue;
      const auto v = check(line);
      if (!v) continue;
      line.violated = true;
      result_.violations.push_back(*v);
      const auto p = line_position(id);
      if (!queued[id]) next.push_back(id), queued[id] = 1;
      for (std::size_t a = 0; a < 4; ++a)
        for (int d : {-1, 1}) {
          auto q = p;
          if ((d < 0 && q[a] == 0) || (d > 0 && q[a] + 1 >= extent(a))) continue;
          q[a] = static_cast<std::uint32_t>(static_cast<int>(q[a]) + d);
          const std::size_t n = line_id(q);
          if (!queued[n]) next.push_back(n), queued[n] = 1;
        }
    }
    return next;
  };
  std::vector<std::size_t> all(lines_.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  todo = scan(all);
  while (!todo.empty()) {
    std::sort(todo.begin(), todo.end());
    parallel(todo, [&](std::size_t id) { resolve_fully(id); });
    todo = scan(todo);
  }
}

// Gives every cell of a line its region and method: G above the stop boundary (by physics), Y
// from the avoidance threshold, the labels below it; `from` names the simulated cells behind
// each inferred cell (in the line, or at the same level on the corners it was inferred from).
void Search::fill(std::size_t id) {
  Line& line = lines_[id];
  std::vector<std::size_t> simulated;
  for (std::size_t i = 0; i < line.cells.size(); ++i)
    if (is_simulated(line.cells[i])) simulated.push_back(i);
  for (std::size_t i = 0; i < line.cells.size(); ++i) {
    Cell& c = result_.cells[line.cells[i]];
    if (c.method == Method::kSimulated) continue;
    c.from.clear();
    if (i >= line.t_g) {
      c.region = Region::kG;
      c.method = Method::kStop;
      continue;
    }
    // Its run [begin, end), and whether the line's own simulations settled it.
    std::size_t begin = line.t_e, end = line.t_a;
    bool from_line = line.labels_sampled;
    const bool y = i >= line.t_a;
    if (i < line.t_e) {
      const bool g = i < line.t_eg;
      c.region = g ? Region::kG : Region::kY;
      begin = g ? 0 : line.t_eg;
      end = g ? line.t_eg : line.t_e;
      from_line = g || !line.early_predicted;  // an early run's G part is always the line's own
    } else if (y) {
      c.region = Region::kY;
      begin = line.t_a;
      end = line.t_g;
      from_line = line.thresholds_searched;
    } else {
      c.region = nothing_to_mitigate(line.cells[i]) ? Region::kR : line.labels[i];
    }
    c.method = from_line ? Method::kLine : Method::kBox;
    // The line's simulated cells nearest below and above it within [lo, hi).
    const auto bounding = [&](std::size_t lo, std::size_t hi) {
      const auto above = std::upper_bound(simulated.begin(), simulated.end(), i);
      if (above != simulated.begin() && *std::prev(above) >= lo) c.from.push_back(line.cells[*std::prev(above)]);
      if (above != simulated.end() && *above < hi) c.from.push_back(line.cells[*above]);
    };
    if (from_line) bounding(begin, end);  // the simulated cells around it in its run
    if (c.from.empty())
      corner_sources(line, y || i < line.t_e ? line.threshold_corners : line.label_corners, i, c.from);
    if (c.from.empty()) bounding(0, line.cells.size());  // R by the rule where nothing was sampled
    if (c.from.empty()) corner_sources(line, line.threshold_corners, i, c.from);
  }
}

// The simulated cells at the level of cell i (or the nearest) on the lines its labels came from,
// or on the lines beside it when it has none.
void Search::corner_sources(const Line& line, const std::vector<std::uint32_t>& corners, std::size_t i,
                            std::vector<std::uint32_t>& from) const {
  for (std::uint32_t corner : corners) {
    const Line& other = lines_[corner];
    if (other.cells.empty()) continue;
    auto at = static_cast<std::size_t>(
        std::lower_bound(other.position.begin(), other.position.end(), line.position[i]) - other.position.begin());
    if (at == other.cells.size() ||
        (at > 0 && line.position[i] - other.position[at - 1] < other.position[at] - line.position[i]))
      --at;
    const std::uint32_t cell = other.cells[at];
    if (is_simulated(cell)) {
      from.push_back(cell);
      continue;
    }
    // The corner's own nearest simulations at that level's run.
    for (std::size_t k = at; k-- > 0;)
      if (is_simulated(other.cells[k])) {
        from.push_back(other.cells[k]);
        break;
      }
    for (std::size_t k = at + 1; k < other.cells.size(); ++k)
      if (is_simulated(other.cells[k])) {
        from.push_back(other.cells[k]);
        break;
      }
  }
  std::sort(from.begin(), from.end());
  from.erase(std::unique(from.begin(), from.end()), from.end());
  if (from.size() > kMaxFrom) from.resize(kMaxFrom);
}

// A random sample of the cells inferred from other simulations (not the analytic stop cells, which
// are exact by construction), simulated: the observed disagreement rate and its Wilson interval.
void Search::verify() {
  std::vector<std::uint32_t> population;
  for (std::size_t c = 0; c < result_.cells.size(); ++c)
    if (result_.cells[c].method == Method::kLine || result_.cells[c].method == Method::kBox)
      population.push_back(static_cast<std::uint32_t>(c));
  result_.verify_population = population.size();
  const std::size_t automatic = std::clamp<std::size_t>(result_.feasible / 200, 20, 500);
  const std::size_t k = std::min(options_.verify_sample.value_or(automatic), population.size());
  std::mt19937_64 random(options_.seed);
  for (std::size_t i = 0; i < k; ++i) {  // a partial Fisher-Yates shuffle: the same sample everywhere
    const std::size_t j = i + static_cast<std::size_t>(random() % (population.size() - i));
    std::swap(population[i], population[j]);
  }
  population.resize(k);
  std::sort(population.begin(), population.end());
  std::vector<Region> inferred(k);
  for (std::size_t i = 0; i < k; ++i) inferred[i] = result_.cells[population[i]].region;
  simulate_all(population, Purpose::kVerification);
  for (std::size_t i = 0; i < k; ++i)
    if (result_.cells[population[i]].region != inferred[i]) result_.verify_disagreements.push_back(population[i]);
  result_.verify_sampled = k;
  result_.disagreement = scenario::wilson_interval(static_cast<double>(result_.verify_disagreements.size()),
                                                   static_cast<double>(k), options_.confidence);
}

void Search::finish() {
  result_.simulated = simulated_.load();
  for (std::size_t p = 0; p < kPurposes; ++p) result_.simulated_for[p] = simulated_for_[p].load();
  for (const Line& line : lines_) {
    result_.lines_resolved += line.thresholds_searched || line.labels_sampled ? 1 : 0;
    result_.lines_inferred += line.thresholds_searched || line.labels_sampled ? 0 : 1;
    result_.lines_fully_resolved += line.full ? 1 : 0;
  }
}

}  // namespace emrm::campaign::adaptive::detail
