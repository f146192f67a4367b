// The trace CSV of played trajectories (trace.hpp).

#include "emrm/openscenario/trace.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <vector>

namespace emrm::openscenario {
namespace {
constexpr std::string_view kHeader = "t,actor,x,y,heading,speed";
}

void write_trace_csv(std::ostream& out, const Trajectories& trajectories) {
  out << kHeader << '\n';
  std::size_t rows = 0;
  for (const auto& [name, samples] : trajectories) rows = std::max(rows, samples.size());
  // Every entity has a sample at each time, so row i of each, in the map's (name) order.
  for (std::size_t i = 0; i < rows; ++i)
    for (const auto& [name, samples] : trajectories) {
      if (i >= samples.size()) continue;
      const Sample& s = samples[i];
      out << fmt::format("{:.17g},{},{:.17g},{:.17g},{:.17g},{:.17g}\n", s.t_s, name, s.x_m, s.y_m, s.heading_rad,
                         s.speed_mps);
    }
}

Trajectories read_trace_csv(std::istream& in, const std::string& file) {
  Trajectories out;
  std::string line;
  int line_number = 1;
  if (!std::getline(in, line) || line != kHeader)
    throw InputError({file, 1, 1}, fmt::format("expected the header '{}'", kHeader));
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    std::vector<std::string_view> fields;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= line.size(); ++i)
      if (i == line.size() || line[i] == ',') {
        fields.emplace_back(line.data() + start, i - start);
        start = i + 1;
      }
    if (fields.size() != 6)
      throw InputError({file, line_number, 1}, fmt::format("expected 6 fields, got {}", fields.size()));
    double values[5] = {};
    const std::size_t numeric[5] = {0, 2, 3, 4, 5};
    for (std::size_t k = 0; k < 5; ++k) {
      const std::string_view f = fields[numeric[k]];
      const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), values[k]);
      if (ec != std::errc() || end != f.data() + f.size())
        throw InputError({file, line_number, static_cast<int>(f.data() - line.data()) + 1},
                         fmt::format("expected a number, got '{}'", f));
    }
    out[std::string(fields[1])].push_back({values[0], values[1], values[2], values[3], values[4]});
  }
  return out;
}

}  // namespace emrm::openscenario
