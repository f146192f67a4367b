// The CSV form of a covering array (`emrm ca`).

#include "emrm/scenario/covering_array_io.hpp"

#include <fmt/format.h>

#include <cassert>
#include <utility>
#include <vector>

#include "emrm/core/text.hpp"

namespace emrm::scenario {

std::string covering_array_csv(const CoveringArray& ca, const PictModel* model) {
  assert(model == nullptr || model->parameters().size() == ca.levels.size());
  core::Row header;
  for (std::size_t c = 0; c < ca.levels.size(); ++c)
    header.push_back(model ? model->parameters()[c].name : fmt::format("p{}", c + 1));
  std::vector<core::Row> rows;
  for (const auto& r : ca.rows) {
    core::Row out;
    for (std::size_t c = 0; c < r.size(); ++c)
      out.push_back(model ? model->parameters()[c].values[static_cast<std::size_t>(r[c])] : std::to_string(r[c]));
    rows.push_back(std::move(out));
  }
  return core::csv_table(header, rows);
}

}  // namespace emrm::scenario
