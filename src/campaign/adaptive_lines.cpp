// The adaptive search's lattice geometry: its lines, where each lies, the first boxes of lines.

#include "adaptive_search.hpp"

namespace emrm::campaign::adaptive::detail {

void Search::build_lines() {
  std::size_t count = 1;
  for (std::size_t a = 0; a < 4; ++a) count *= extent(a);
  lines_.resize(count);
  result_.lines = count;
  std::array<std::uint32_t, 4> p{};
  for (std::size_t id = 0; id < count; ++id) {
    Line& line = lines_[id];
    std::array<std::size_t, kAxes> level{};
    for (std::size_t a = 0; a < 4; ++a) level[line_axes_[a]] = order_[line_axes_[a]][p[a]];
    for (std::uint32_t j = 0; j < lattice_.levels[monotone_].size(); ++j) {
      level[monotone_] = order_[monotone_][j];
      const std::size_t cell = lattice_.index(level);
      if (!oracle_.feasible(cell)) continue;
      line.cells.push_back(static_cast<std::uint32_t>(cell));
      line.position.push_back(j);
      ++result_.feasible;
    }
    for (std::size_t a = 4; a-- > 0;) {  // next position, the last line axis fastest
      if (++p[a] < extent(a)) break;
      p[a] = 0;
    }
  }
}

std::array<std::uint32_t, 4> Search::line_position(std::size_t id) const noexcept {
  std::array<std::uint32_t, 4> p{};
  for (std::size_t a = 4; a-- > 0;) {
    p[a] = static_cast<std::uint32_t>(id % extent(a));
    id /= extent(a);
  }
  return p;
}

// Lines searched per factor before refining, unless the options say: for thresholds 4 when the
// lines vary in one factor, 3 when in more (the first lattice's share of the lines stays small);
// for labels 2, the domain's corners, since a label boundary is refined across the factor it
// crosses only.
std::size_t Search::initial_levels(Question q) const noexcept {
  if (options_.initial_levels > 0) return options_.initial_levels;
  if (q == Question::kLabels) return 2;
  std::size_t varying = 0;
  for (std::size_t a = 0; a < 4; ++a) varying += extent(a) > 1;
  return varying <= 1 ? 4 : 3;
}

// Each factor sampled at about `initial_levels` positions, always its first and last.
std::vector<Box> Search::initial_boxes(std::size_t levels) const {
  std::array<std::vector<std::uint32_t>, 4> samples;
  for (std::size_t a = 0; a < 4; ++a) {
    const std::uint32_t n = extent(a);
    const std::uint32_t stride =
        n <= 1 ? 1 : std::max<std::uint32_t>(1, static_cast<std::uint32_t>((n - 1 + levels - 2) / (levels - 1)));
    for (std::uint32_t p = 0; p + 1 < n; p += stride) samples[a].push_back(p);
    samples[a].push_back(n - 1);
  }
  std::vector<Box> boxes;
  std::array<std::size_t, 4> k{};
  const auto intervals = [&](std::size_t a) { return std::max<std::size_t>(1, samples[a].size() - 1); };
  while (true) {
    Box box;
    for (std::size_t a = 0; a < 4; ++a) {
      box.lo[a] = samples[a][k[a]];
      box.hi[a] = samples[a].size() > 1 ? samples[a][k[a] + 1] : samples[a][0];
    }
    boxes.push_back(box);
    std::size_t a = 4;
    while (a-- > 0) {
      if (++k[a] < intervals(a)) break;
      k[a] = 0;
    }
    if (a == static_cast<std::size_t>(-1)) break;
  }
  return boxes;
}

}  // namespace emrm::campaign::adaptive::detail
