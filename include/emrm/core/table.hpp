#pragma once

// A results table with its title and notes, and its three renderings: Markdown (with the notes),
// CSV and a LaTeX `tabular`. The tables of campaign (ours beside the paper's) and of reproduce are
// built as this one type and written by write_table.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/text.hpp"

namespace emrm::core {

/// What a table shows for a value that does not exist (no cells, not in the paper).
inline constexpr std::string_view kNoValue = "—";

/// A table with its title and a closing paragraph (why ours and the paper's differ).
struct Table {
  std::string title;
  Row header;
  std::vector<Row> rows;
  std::vector<std::string> notes;  ///< paragraphs after the table
};

/// "# title", the Markdown table, then the notes as paragraphs.
[[nodiscard]] std::string to_markdown(const Table& table);
/// Header and rows only (RFC 4180).
[[nodiscard]] std::string to_csv(const Table& table);
/// A plain `tabular` (one l column then c columns, \hline rules) with every cell escaped, preceded
/// by the title as a comment; notes are not included.
[[nodiscard]] std::string to_latex(const Table& table);
/// Escapes LaTeX's special characters (\ { } $ & # ^ _ % ~ < >) so the text prints as written, and
/// writes the symbols our tables use (— μ Δ ≥ ≤) in LaTeX so no extra package is needed.
[[nodiscard]] std::string latex_escape(std::string_view text);

/// A number for a table: `decimals` places, kNoValue for NaN, "inf" or "-inf" for infinities.
[[nodiscard]] std::string format_number(double value, int decimals);

/// TABLES_DIR/STEM.md, .csv and .tex with their contents, for write_files.
[[nodiscard]] std::vector<FileContent> table_files(const std::filesystem::path& tables_dir, const std::string& stem,
                                                   const Table& table);

/// Writes table_files, all three or none (write_files, creating the folder); returns the files
/// written. Throws emrm::Error when a file cannot be written.
std::vector<std::filesystem::path> write_table(const std::filesystem::path& tables_dir, const std::string& stem,
                                               const Table& table);

}  // namespace emrm::core
