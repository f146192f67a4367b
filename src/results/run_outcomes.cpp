#include "emrm/results/run_outcomes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <type_traits>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"

namespace emrm::results {
namespace {

std::string number(double v) { return fmt::format("{:.6g}", v); }

// The header: the fixed columns, with the factors' where the list has them.
core::Row header_of(const std::vector<std::string>& factors) {
  core::Row header;
  const ScenarioOutcome none;
  ScenarioOutcome::visit_fields(none, [&](const char* column, const auto& field, auto...) {
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(field)>, std::vector<double>>)
      header.insert(header.end(), factors.begin(), factors.end());
    else
      header.emplace_back(column);
  });
  return header;
}

// A number of column `column`: core's parsers, refused at `where`.
template <class T>
T parse_number(const std::string& text, const SourceLocation& where, const char* column) {
  std::optional<T> value;
  if constexpr (std::is_integral_v<T>)
    value = core::parse_whole_number<T>(text);
  else
    value = core::parse_finite_number(text);
  if (!value)
    throw InputError(where,
                     fmt::format("{}: expected {}, got '{}'", column,
                                 std::is_integral_v<T> ? "a whole number" : "a finite number", text.substr(0, 40)));
  return *value;
}

// One cell of a row into `field`; a blank stays the default where `blank_allowed`.
template <class T>
void read_cell(const core::CsvRecord& record, std::size_t c, const std::string& file, const char* column, T& field,
               bool blank_allowed) {
  const std::string& text = record.fields[c];
  const SourceLocation where{file, record.lines[c], record.columns[c]};
  if (blank_allowed && text.empty()) return;  // an infeasible scenario's blank
  if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    field = core::split_words(text);
  } else if constexpr (std::is_same_v<T, bool>) {
    if (text != "yes" && text != "no")
      throw InputError(where, fmt::format("{}: expected yes or no, got '{}'", column, text.substr(0, 40)));
    field = text == "yes";
  } else if constexpr (std::is_arithmetic_v<T>) {
    field = parse_number<T>(text, where, column);
  } else {
    field = text;
  }
}

}  // namespace

std::string run_outcomes_csv(const RunOutcomes& outcomes) {
  std::vector<core::Row> rows;
  for (const auto& o : outcomes.scenarios) {
    core::Row row;
    ScenarioOutcome::visit_fields(o, [&](const char*, const auto& field, auto... feasible_only) {
      using T = std::remove_cvref_t<decltype(field)>;
      if (sizeof...(feasible_only) > 0 && !o.feasible) {  // blank for an infeasible scenario
        row.emplace_back();
        return;
      }
      if constexpr (std::is_same_v<T, std::vector<double>>) {
        for (const double v : field) row.push_back(number(v));
      } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
        row.push_back(core::join(field, " "));
      } else if constexpr (std::is_same_v<T, bool>) {
        row.emplace_back(field ? "yes" : "no");
      } else if constexpr (std::is_same_v<T, double>) {
        row.push_back(number(field));
      } else if constexpr (std::is_same_v<T, int>) {
        row.push_back(std::to_string(field));
      } else {
        row.push_back(field);
      }
    });
    rows.push_back(std::move(row));
  }
  return core::csv_table(header_of(outcomes.factors), rows);
}

RunOutcomes read_run_outcomes(const std::filesystem::path& path) {
  const std::string file = path.string();
  const auto records = core::parse_csv(core::read_input_file(path), file);
  RunOutcomes out;
  if (!records.empty()) {  // the factor columns: between cell and malfunctions
    const core::Row& given = records.front().fields;
    const auto cell = std::find(given.begin(), given.end(), "cell");
    const auto malfunctions = std::find(given.begin(), given.end(), "malfunctions");
    if (cell != given.end() && malfunctions != given.end() && cell < malfunctions)
      out.factors.assign(cell + 1, malfunctions);
  }
  const core::Row header = header_of(out.factors);
  if (records.empty() || records.front().fields != header)
    throw InputError({file, 1, 1}, fmt::format("expected the header of an outcomes.csv: {}",
                                               core::join(header_of({"FACTOR..."}), ",")));
  for (std::size_t i = 1; i < records.size(); ++i) {
    const auto& record = records[i];
    core::check_row_length(record, header.size(), file);
    ScenarioOutcome o;
    std::size_t c = 0;
    ScenarioOutcome::visit_fields(o, [&](const char* column, auto& field, auto... feasible_only) {
      using T = std::remove_cvref_t<decltype(field)>;
      if constexpr (std::is_same_v<T, std::vector<double>>) {
        for (const auto& factor : out.factors) {
          const SourceLocation where{file, record.lines[c], record.columns[c]};
          field.push_back(parse_number<double>(record.fields[c++], where, factor.c_str()));
        }
      } else {
        read_cell(record, c++, file, column, field, sizeof...(feasible_only) > 0);
      }
    });
    out.scenarios.push_back(std::move(o));
    out.lines.push_back(record.lines.front());
  }
  return out;
}

}  // namespace emrm::results
