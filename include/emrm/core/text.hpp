#pragma once

// Small text helpers shared by the tables every command writes.

#include <charconv>
#include <concepts>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace emrm::core {

using Row = std::vector<std::string>;

/// Joins `parts` with `separator`.
[[nodiscard]] std::string join(const std::vector<std::string>& parts, std::string_view separator);

/// The words of a text separated by blanks (spaces, tabs, newlines), without empty ones.
[[nodiscard]] std::vector<std::string> split_words(std::string_view text);

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

/// Throws InputError when `row` has another number of fields than its document's header,
/// `expected` (a truncated or malformed row): at the first field too many, or at the last field of
/// a row too short (file_name:line:column).
void check_row_length(const CsvRecord& row, std::size_t expected, const std::string& file_name);

/// A number as people and other tools read it: 15 significant digits at most, so that the last bit
/// of a sum or a unit conversion (0.1 + 0.2, 4.9500000000000002) does not show, while every value
/// within 5e-15 of its own keeps all its digits ("0.30000000000000004" is written "0.3"). −0 is 0.
[[nodiscard]] std::string readable_number(double value);

/// The finite number the whole of `text` spells (strtod's syntax), or nothing: empty text, trailing
/// characters, NaN, infinities and out-of-range values are not numbers here.
[[nodiscard]] std::optional<double> parse_finite_number(const std::string& text);

/// The whole number the whole of `text` spells in decimal (a leading '-' for a signed T), or
/// nothing: empty text, other characters, a value T cannot hold.
template <std::integral T>
[[nodiscard]] std::optional<T> parse_whole_number(std::string_view text) {
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

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

/// An output file written whole or not at all (docs/outputs.md, "Atomic outputs"): the text goes
/// to a temporary beside the target, `NAME.tmp.PID.N` (the process id and a counter, so that two
/// processes or threads writing the same folder never share one), which commit() renames onto the
/// target once everything reached the disk. Destroyed without commit() — an exception on the way —
/// it removes the temporary, so a failed command leaves neither a half-written file nor a
/// temporary. For a file written in pieces (the exports stream a whole store); write_file and
/// write_files use it for text held in memory.
class OutputFile {
 public:
  /// Creates the target's folders and opens the temporary. Throws emrm::Error when a folder cannot
  /// be created, the target is a folder, or the temporary cannot be opened.
  explicit OutputFile(std::filesystem::path path);
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();

  [[nodiscard]] std::ostream& stream() noexcept { return out_; }
  [[nodiscard]] const std::filesystem::path& path() const noexcept { return path_; }
  /// Closes the temporary. Throws emrm::Error when anything written to it was lost (a full disk
  /// shows only when the last buffer is flushed, here).
  void close();
  /// close(), then renames the temporary onto the target. Throws emrm::Error when it cannot.
  void commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path temporary_;
  std::ofstream out_;
  bool committed_ = false;
};

/// Writes a file atomically (an OutputFile), creating parent folders.
/// Throws emrm::Error when the file cannot be written; the target is then as it was.
void write_file(const std::filesystem::path& path, std::string_view content);

/// A file's path and its whole content, for write_files.
struct FileContent {
  std::filesystem::path path;
  std::string content;
};

/// Writes files that belong together (a plan, an analysis, a run's tables) all or nothing, as far
/// as a file system allows: every file complete in its temporary first, then the renames, one after
/// another. A failure while writing (a full disk, a target that is a folder) leaves every target as
/// it was and no temporary. Throws as write_file.
void write_files(const std::vector<FileContent>& files);

}  // namespace emrm::core
