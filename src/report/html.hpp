#pragma once

// Private to the report: what the report's sections share (HTML tables, reading side files).

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/core/text.hpp"

namespace emrm::report::detail {

/// A table whose first record is the header, every cell escaped, in a horizontally scrolling box.
[[nodiscard]] std::string html_table(const std::vector<core::CsvRecord>& rows);
/// The same from a header and rows.
[[nodiscard]] std::string html_table(const core::Row& header, const std::vector<core::Row>& rows);

/// The file's text, or "" when it is not a regular file.
[[nodiscard]] std::string read_or_empty(const std::filesystem::path& path);

}  // namespace emrm::report::detail
