#include "emrm/core/text.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <system_error>

#include "emrm/core/error.hpp"

namespace emrm::core {

std::string join(const std::vector<std::string>& parts, std::string_view separator) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (i > 0) out += separator;
    out += parts[i];
  }
  return out;
}

std::string csv_line(const Row& fields) {
  std::string out;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) out += ',';
    const std::string& f = fields[i];
    if (f.find_first_of(",\"\n\r") == std::string::npos) {
      out += f;
      continue;
    }
    out += '"';
    for (char c : f) {
      if (c == '"') out += '"';
      out += c;
    }
    out += '"';
  }
  out += '\n';
  return out;
}

std::string readable_number(double value) { return fmt::format("{:.15g}", value == 0.0 ? 0.0 : value); }

std::optional<double> parse_finite_number(const std::string& text) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (text.empty() || used != text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::vector<CsvRecord> parse_csv(std::string_view text, const std::string& file_name) {
  std::vector<CsvRecord> records;
  CsvRecord record;
  std::string field;
  int line = 1;
  int column = 1;
  int field_line = 1;
  int field_column = 1;
  bool quoted = false;
  bool after_quote = false;
  const auto end_field = [&] {
    record.fields.push_back(std::move(field));
    record.lines.push_back(field_line);
    record.columns.push_back(field_column);
    field.clear();
    after_quote = false;
  };
  const auto end_record = [&] {
    end_field();
    const bool blank = record.fields.size() == 1 && record.fields[0].empty();
    if (!blank) records.push_back(std::move(record));
    record = CsvRecord{};
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
        column += 2;
        continue;
      }
      if (c == '"') {
        quoted = false;
        after_quote = true;
      } else {
        field += c;
      }
      if (c == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
      continue;
    }
    if (c == ',') {
      end_field();
      field_line = line;
      field_column = ++column;
      continue;
    }
    if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') continue;
    if (c == '\n') {
      end_record();
      field_line = ++line;
      field_column = column = 1;
      continue;
    }
    if (after_quote)
      throw InputError({file_name, line, column}, "unexpected text after a closing quote; expected ',' or a new line");
    if (c == '"' && field.empty()) {
      quoted = true;
      ++column;
      continue;
    }
    field += c;
    ++column;
  }
  if (quoted) throw InputError({file_name, field_line, field_column}, "unterminated quoted field");
  if (!field.empty() || !record.fields.empty() || after_quote) end_record();
  return records;
}

void check_row_length(const CsvRecord& row, std::size_t expected, const std::string& file_name) {
  if (row.fields.size() == expected) return;
  // At the first field too many, or at the last of too few.
  const std::size_t at = std::min(expected, row.fields.size() - 1);
  throw InputError({file_name, row.lines[at], row.columns[at]},
                   fmt::format("expected {} fields as in the header, got {} (a truncated or malformed row)", expected,
                               row.fields.size()));
}

std::string csv_table(const Row& header, const std::vector<Row>& rows) {
  std::string out = csv_line(header);
  for (const auto& row : rows) out += csv_line(row);
  return out;
}

namespace {
std::string markdown_cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n')
      out += "<br>";
    else
      out += c;
  }
  return out;
}
}  // namespace

std::string markdown_table(const Row& header, const std::vector<Row>& rows) {
  auto line = [](const Row& cells) {
    std::string out = "|";
    for (const auto& c : cells) out += " " + markdown_cell(c) + " |";
    return out + "\n";
  };
  std::string out = line(header) + "|";
  for (std::size_t i = 0; i < header.size(); ++i) out += " --- |";
  out += "\n";
  for (const auto& row : rows) out += line(row);
  return out;
}

namespace {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const bool same =
          std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? std::size_t{0} : std::size_t{1})});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::vector<std::string> split_words(std::string_view text) {
  std::vector<std::string> out;
  std::size_t from = 0;
  while (true) {
    from = text.find_first_not_of(" \t\n\r\f\v", from);
    if (from == std::string_view::npos) return out;
    const std::size_t to = std::min(text.find_first_of(" \t\n\r\f\v", from), text.size());
    out.emplace_back(text.substr(from, to - from));
    from = to;
  }
}

std::string counted(std::size_t n, std::string_view one, std::string_view many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

std::string did_you_mean(std::string_view name, const std::vector<std::string>& candidates) {
  // A name that starts another is a shortened one ("--speed" for "--speed-kph"): that one first.
  for (const auto& c : candidates)
    if (name.size() >= 3 && c.size() > name.size() && c.compare(0, name.size(), name) == 0)
      return fmt::format(" (did you mean '{}'?)", c);
  const std::string* best = nullptr;
  std::size_t best_distance = 0;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(name, c);
    if (best == nullptr || d < best_distance) {
      best = &c;
      best_distance = d;
    }
  }
  if (best == nullptr || best_distance > std::max<std::size_t>(2, name.size() / 3)) return {};
  return fmt::format(" (did you mean '{}'?)", *best);
}

std::string read_input_file(const std::filesystem::path& path) {
  const SourceLocation where{path.string(), 0, 0};
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw InputError(where, "the file does not exist");
  if (std::filesystem::is_directory(status)) throw InputError(where, "this is a folder; expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(where, "cannot open the file (no permission to read it?)");
  // Read in pieces up to the cap, so that a device or a pipe without end cannot exhaust memory.
  std::string text;
  std::array<char, 1 << 16> buffer{};
  while (in.read(buffer.data(), buffer.size()) || in.gcount() > 0) {
    text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxInputFileBytes)
      throw InputError(
          where, fmt::format("the file is larger than {} MiB; expected an emrm input file", kMaxInputFileBytes >> 20));
  }
  if (in.bad()) throw InputError(where, "cannot read the file");
  // Text is UTF-8 from here on (every name may reach a JSON writer): a byte-order mark is dropped, a
  // byte that is not UTF-8 is bad input at its line and column.
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
  if (const auto bad = first_invalid_utf8(text)) {
    const std::string_view before = std::string_view(text).substr(0, *bad);
    const auto newline = before.rfind('\n');
    const auto line = static_cast<int>(std::count(before.begin(), before.end(), '\n')) + 1;
    const auto column = static_cast<int>(newline == std::string_view::npos ? *bad + 1 : *bad - newline);
    throw InputError({path.string(), line, column},
                     fmt::format("byte 0x{:02X} is not UTF-8; expected text in UTF-8 (save the file as UTF-8)",
                                 static_cast<unsigned char>(text[*bad])));
  }
  return text;
}

std::optional<std::size_t> first_invalid_utf8(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const auto continuation = [&](std::size_t i) { return i < text.size() && (byte(i) & 0xC0) == 0x80; };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char b = byte(i);
    std::size_t length = 0;
    unsigned char low = 0x80, high = 0xBF;  // the allowed range of the second byte
    if (b < 0x80)
      length = 1;
    else if (b >= 0xC2 && b <= 0xDF)
      length = 2;
    else if (b >= 0xE0 && b <= 0xEF) {
      length = 3;
      if (b == 0xE0) low = 0xA0;   // no overlong forms
      if (b == 0xED) high = 0x9F;  // no surrogates
    } else if (b >= 0xF0 && b <= 0xF4) {
      length = 4;
      if (b == 0xF0) low = 0x90;   // no overlong forms
      if (b == 0xF4) high = 0x8F;  // nothing above U+10FFFF
    } else {
      return i;
    }
    if (length > 1 && (i + 1 >= text.size() || byte(i + 1) < low || byte(i + 1) > high)) return i;
    for (std::size_t k = 2; k < length; ++k)
      if (!continuation(i + k)) return i;
    i += length;
  }
  return std::nullopt;
}

namespace {

// A name beside `path` that no other process (the pid) and no other thread of this one (the
// counter) uses at the same time.
std::filesystem::path temporary_for(const std::filesystem::path& path) {
  static std::atomic<unsigned long> counter{0};
  return path.string() + fmt::format(".tmp.{}.{}", ::getpid(), counter++);
}

}  // namespace

OutputFile::OutputFile(std::filesystem::path path) : path_(std::move(path)) {
  std::error_code ec;
  if (path_.has_parent_path()) std::filesystem::create_directories(path_.parent_path(), ec);
  if (ec) throw Error(fmt::format("cannot create folder '{}': {}", path_.parent_path().string(), ec.message()));
  // The rename would fail at the end; failing now writes nothing (write_files: none of the files).
  if (std::filesystem::is_directory(path_, ec))
    throw Error(fmt::format("cannot write '{}': it is a folder", path_.string()));
  temporary_ = temporary_for(path_);
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    const std::string why = std::generic_category().message(errno);
    std::filesystem::remove(temporary_, ec);
    throw Error(fmt::format("cannot write '{}': {}", path_.string(), why));
  }
}

OutputFile::~OutputFile() {
  if (committed_) return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
}

void OutputFile::close() {
  if (out_.is_open()) out_.close();
  if (!out_) throw Error(fmt::format("cannot write '{}' (is the disk full?)", path_.string()));
}

void OutputFile::commit() {
  if (committed_) return;
  close();
  std::error_code ec;
  std::filesystem::rename(temporary_, path_, ec);
  if (ec) throw Error(fmt::format("cannot write '{}': {}", path_.string(), ec.message()));
  committed_ = true;
}

void write_file(const std::filesystem::path& path, std::string_view content) {
  OutputFile file(path);
  file.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  file.commit();
}

void write_files(const std::vector<FileContent>& files) {
  // Every file complete in its temporary before the first rename: a failure on the way (the
  // destructors remove the temporaries) changes none of the targets.
  std::vector<std::unique_ptr<OutputFile>> staged;
  for (const auto& f : files) {
    staged.push_back(std::make_unique<OutputFile>(f.path));
    staged.back()->stream().write(f.content.data(), static_cast<std::streamsize>(f.content.size()));
    staged.back()->close();
  }
  for (auto& file : staged) file->commit();
}

}  // namespace emrm::core
