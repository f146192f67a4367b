#pragma once

// Small text helpers shared by the tables every command writes.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace emrm::core {

using Row = std::vector<std::string>;

/// Joins `parts` with `separator`.
[[nodiscard]] std::string join(const std::vector<std::string>& parts, std::string_view separator);

/// "1 warning", "2 warnings": `n` and the word for its number.
[[nodiscard]] std::string counted(std::size_t n, std::string_view one, std::string_view many);

/// " (did you mean 'severity'?)" for a misspelt `name`: a candidate it starts (a shortened name),
/// else the candidate nearest to it by edit distance (ignoring case) when that is within a third of
/// the name's length (at least 2 edits); else "".
[[nodiscard]] std::string did_you_mean(std::string_view name, const std::vector<std::string>& candidates);

/// One CSV line (RFC 4180 quoting, "\n" terminated).
[[nodiscard]] std::string csv_line(const Row& fields);
/// A whole CSV document: header then rows.
[[nodiscard]] std::string csv_table(const Row& header, const std::vector<Row>& rows);
/// A GitHub-flavoured Markdown table; '|' and newlines inside cells are escaped.
[[nodiscard]] std::string markdown_table(const Row& header, const std::vector<Row>& rows);

/// One record of a CSV document with where each field starts (1-based line and column).
struct CsvRecord {
  Row fields;
  std::vector<int> lines;
  std::vector<int> columns;
};

/// Parses RFC 4180 CSV (quoted fields may hold commas, quotes and newlines; CRLF accepted; blank
/// lines skipped). Throws InputError at `file_name`:line:column for an unterminated quote or text
/// after a closing quote.
[[nodiscard]] std::vector<CsvRecord> parse_csv(std::string_view text, const std::string& file_name);

/// The finite number the whole of `text` spells (strtod's syntax), or nothing: empty text, trailing
/// characters, NaN, infinities and out-of-range values are not numbers here.
[[nodiscard]] std::optional<double> parse_finite_number(const std::string& text);

/// The largest input file emrm reads (64 MiB): every input is a hand-written or generated text of
/// far less; the cap keeps a device or an endless pipe from exhausting memory.
inline constexpr std::size_t kMaxInputFileBytes = std::size_t{64} << 20;

/// The offset of the first byte of `text` that does not begin a well-formed UTF-8 sequence
/// (overlong forms, surrogates and code points above U+10FFFF are not), or nullopt.
[[nodiscard]] std::optional<std::size_t> first_invalid_utf8(std::string_view text);

/// The whole content of a user's input file, as UTF-8 without a byte-order mark. Throws InputError
/// naming the file when it does not exist, is a folder, cannot be opened or read, exceeds
/// kMaxInputFileBytes, or holds a byte that is not UTF-8 (at its line and column).
[[nodiscard]] std::string read_input_file(const std::filesystem::path& path);

/// Writes a file atomically (temporary file, then rename), creating parent folders.
/// Throws emrm::Error when the file cannot be written.
void write_file(const std::filesystem::path& path, std::string_view content);

}  // namespace emrm::core
