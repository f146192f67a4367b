#include "html.hpp"

#include "emrm/core/process.hpp"
#include "emrm/report/report.hpp"

namespace emrm::report::detail {

std::string html_table(const std::vector<core::CsvRecord>& rows) {
  std::string out = "<div class=\"scroll\"><table>\n";
  for (std::size_t r = 0; r < rows.size(); ++r) {
    out += "<tr>";
    for (const auto& cell : rows[r].fields)
      out += (r == 0 ? "<th>" : "<td>") + html_escape(cell) + (r == 0 ? "</th>" : "</td>");
    out += "</tr>\n";
  }
  return out + "</table></div>\n";
}

std::string html_table(const core::Row& header, const std::vector<core::Row>& rows) {
  std::vector<core::CsvRecord> records;
  records.push_back({header, {}, {}});
  for (const auto& r : rows) records.push_back({r, {}, {}});
  return html_table(records);
}

std::string read_or_empty(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) ? core::read_file(path) : std::string();
}

}  // namespace emrm::report::detail
