#pragma once

// Private to the results store: its cells and outcomes tables made from the records' field lists
// (CellRecord::visit_fields, OutcomeRecord::visit_fields; docs/architecture.md, "The record field
// list"). A field's C++ type decides its column: a number is INTEGER or REAL, text, an enum (by its
// name), the seed (an unsigned 64-bit number SQLite's integers cannot hold) and a list (words
// joined by a space) are TEXT; a field kept with kInfinityIsNull is a REAL that may be NULL; the
// factors are a REAL column per key of the scene's factor table. Every column is NOT NULL but those.

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/core/text.hpp"
#include "store_sql.hpp"

namespace emrm::campaign::detail {

template <class T>
inline constexpr bool kIsFactors = std::is_same_v<T, sim::CellInput>;

/// "name TYPE" of each column of a record's fields, in the list's order (the factors' columns
/// named by `factor_keys`).
template <class Record>
std::vector<std::string> column_definitions(const std::vector<std::string>& factor_keys) {
  std::vector<std::string> out;
  Record record;
  Record::visit_fields(record, [&](const char* name, const auto& field, auto... infinity_is_null) {
    using T = std::remove_cvref_t<decltype(field)>;
    if constexpr (kIsFactors<T>) {
      for (const auto& key : factor_keys) out.push_back(key + " REAL NOT NULL");
    } else if constexpr (sizeof...(infinity_is_null) > 0) {
      out.push_back(fmt::format("{} REAL", name));
    } else if constexpr (std::is_same_v<T, double>) {
      out.push_back(fmt::format("{} REAL NOT NULL", name));
    } else if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, int> || std::is_same_v<T, std::int64_t>) {
      out.push_back(fmt::format("{} INTEGER NOT NULL", name));
    } else {
      out.push_back(fmt::format("{} TEXT NOT NULL", name));
    }
  });
  return out;
}

/// Binds a record's fields to the statement's parameters from `column` on; returns the next one.
template <class Record>
int bind_fields(Statement& statement, int column, const Record& record) {
  Record::visit_fields(record, [&](const char*, const auto& field, auto... infinity_is_null) {
    using T = std::remove_cvref_t<decltype(field)>;
    if constexpr (kIsFactors<T>) {
      for (const double v : field) statement.bind(column++, v);
    } else if constexpr (sizeof...(infinity_is_null) > 0) {
      if (std::isfinite(field))
        statement.bind(column++, field);
      else
        statement.bind_null(column++);
    } else if constexpr (std::is_same_v<T, std::uint64_t>) {
      statement.bind(column++, std::to_string(field));
    } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
      statement.bind(column++, core::join(field, " "));
    } else if constexpr (std::is_same_v<T, std::vector<std::int64_t>>) {
      std::string words;
      for (const std::int64_t i : field) words += (words.empty() ? "" : " ") + std::to_string(i);
      statement.bind(column++, words);
    } else {
      statement.bind(column++, field);
    }
  });
  return column;
}

/// Where each field of a record stands in the rows of a query (found by name), and the factors'
/// columns: those the fields do not name, in table order. A column a field names that the query
/// lacks makes the file not a store.
template <class Record>
class FieldColumns {
 public:
  FieldColumns(const Statement& query, const std::filesystem::path& path, std::span<const std::string_view> keys = {})
      : path_(&path) {
    std::vector<char> named(static_cast<std::size_t>(query.column_count()), 0);
    for (const std::string_view key : keys)
      if (const int c = query.column_named(key); c >= 0) named[static_cast<std::size_t>(c)] = 1;
    Record record;
    Record::visit_fields(record, [&](const char* name, const auto& field, auto...) {
      using T = std::remove_cvref_t<decltype(field)>;
      if constexpr (kIsFactors<T>) {
        positions_.push_back(-1);
      } else {
        const int c = query.column_named(name);
        if (c < 0) not_a_store(path, fmt::format("its table has no column '{}'", name));
        named[static_cast<std::size_t>(c)] = 1;
        positions_.push_back(c);
      }
    });
    for (std::size_t c = 0; c < named.size(); ++c)
      if (named[c] == 0) factors_.push_back(static_cast<int>(c));
    if (factors_.size() > sim::kMaxFactors)
      not_a_store(path, fmt::format("its table has {} factor columns, at most {}", factors_.size(), sim::kMaxFactors));
  }

  /// Reads the row into `record`; `what(name)` names a field in a message ("region of cell g#3").
  void read(const Statement& row, Record& record, const std::function<std::string(const char*)>& what) const {
    std::size_t k = 0;
    const auto named_by = [&what](const char* name) { return [&what, name] { return what(name); }; };
    Record::visit_fields(record, [&](const char* name, auto& field, auto... infinity_is_null) {
      using T = std::remove_cvref_t<decltype(field)>;
      const int c = positions_[k++];
      if constexpr (kIsFactors<T>) {
        std::array<double, sim::kMaxFactors> values{};
        for (std::size_t f = 0; f < factors_.size(); ++f) values[f] = row.real(factors_[f]);
        field = sim::CellInput(std::span<const double>(values.data(), factors_.size()));
      } else if constexpr (sizeof...(infinity_is_null) > 0) {
        field = row.is_null(c) ? std::numeric_limits<double>::infinity() : row.real(c);
      } else if constexpr (std::is_same_v<T, double>) {
        field = row.real(c);
      } else if constexpr (std::is_same_v<T, bool>) {
        field = row.integer(c) != 0;
      } else if constexpr (std::is_same_v<T, int>) {
        field = row.integer(c);
      } else if constexpr (std::is_same_v<T, std::int64_t>) {
        field = row.int64(c);
      } else if constexpr (std::is_same_v<T, std::uint64_t>) {
        field = whole_number<std::uint64_t>(*path_, named_by(name), row.text(c));
      } else if constexpr (std::is_same_v<T, std::string>) {
        field = row.text(c);
      } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
        field = core::split_words(row.text(c));
      } else if constexpr (std::is_same_v<T, std::vector<std::int64_t>>) {
        field.clear();
        for (const auto& word : core::split_words(row.text(c)))
          field.push_back(whole_number<std::int64_t>(*path_, named_by(name), word));
      } else {
        static_assert(core::NamedEnum<T>, "a record field of a type the store cannot keep");
        field = named<T>(*path_, named_by(name), row.text(c));
      }
    });
  }

 private:
  const std::filesystem::path* path_;
  std::vector<int> positions_;  ///< per field in list order; -1 for the factors
  std::vector<int> factors_;
};

}  // namespace emrm::campaign::detail
