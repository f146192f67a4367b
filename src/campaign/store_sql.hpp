#pragma once

// Private to the results store (store.cpp, store_write.cpp, store_read.cpp, store_merge.cpp): the
// SQLite calls its parts share — a prepared statement, a statement run, its errors — and the
// refusal of a file that is not a store.

#include <fmt/format.h>
#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

#include "emrm/core/enum_names.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"

namespace emrm::campaign::detail {

/// Throws emrm::Error naming the store, what failed and SQLite's message.
[[noreturn]] void fail(sqlite3* db, const std::filesystem::path& path, const std::string& what);

/// A text column (NULL, in a store edited by hand, reads as empty), or nothing when its bytes are
/// not UTF-8.
[[nodiscard]] std::optional<std::string> column_text(sqlite3_stmt* stmt, int col);

// A prepared statement that finalizes itself.
class Statement {
 public:
  Statement(sqlite3* db, const std::filesystem::path& path, const char* sql) : db_(db), path_(&path) {
    if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK) fail(db, path, "cannot prepare a query");
  }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement() { sqlite3_finalize(stmt_); }

  /// True when a row is available.
  bool step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail(db_, *path_, "query failed");
  }
  void reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  void bind(int i, const std::string& v) {
    sqlite3_bind_text(stmt_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
  }
  void bind(int i, double v) { sqlite3_bind_double(stmt_, i, v); }
  void bind(int i, std::int64_t v) { sqlite3_bind_int64(stmt_, i, v); }
  void bind(int i, int v) { sqlite3_bind_int(stmt_, i, v); }
  void bind(int i, bool v) { sqlite3_bind_int(stmt_, i, v ? 1 : 0); }
  void bind_null(int i) { sqlite3_bind_null(stmt_, i); }
  /// An enum is stored as its name (core::EnumNames).
  template <core::NamedEnum E>
  void bind(int i, E v) {
    const std::string_view name = core::enum_name(v);
    sqlite3_bind_text(stmt_, i, name.data(), static_cast<int>(name.size()), SQLITE_TRANSIENT);
  }

  /// The text of a column; a store edited by hand may hold bytes that are not UTF-8, refused here
  /// before they reach a JSON or CSV writer.
  std::string text(int col) const {
    if (auto value = column_text(stmt_, col)) return *value;
    throw UsageError(
        fmt::format("{}: error: not an emrm results store (column '{}' holds a byte that is not "
                    "UTF-8; it was damaged or edited)",
                    path_->string(), sqlite3_column_name(stmt_, col)));
  }
  double real(int col) const { return sqlite3_column_double(stmt_, col); }
  /// The number of columns a row of the query has.
  [[nodiscard]] int column_count() const { return sqlite3_column_count(stmt_); }
  /// The position of the result column `name`, or -1.
  int column_named(std::string_view name) const {
    for (int i = 0; i < sqlite3_column_count(stmt_); ++i)
      if (const char* n = sqlite3_column_name(stmt_, i); n != nullptr && name == n) return i;
    return -1;
  }
  std::int64_t int64(int col) const { return sqlite3_column_int64(stmt_, col); }
  int integer(int col) const { return sqlite3_column_int(stmt_, col); }
  bool is_null(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }

 private:
  sqlite3* db_;
  const std::filesystem::path* path_;
  sqlite3_stmt* stmt_ = nullptr;
};

/// Runs `sql` (one statement or several); emrm::Error with SQLite's message when it fails.
void exec(sqlite3* db, const std::filesystem::path& path, const char* sql);

/// Throws UsageError: the file at `path` is not an emrm results store, because `why`.
[[noreturn]] void not_a_store(const std::filesystem::path& path, const std::string& why);

// What holds a stored value, for a message: a text, or a function that writes it, called only when
// the value is refused (a reader names every row's fields, and formats none of them when all is well).
template <typename What>
std::string holder(const What& what) {
  if constexpr (std::is_invocable_v<const What&>)
    return what();
  else
    return std::string(what);
}

// A whole number the store keeps as text, or not_a_store naming what holds something else.
template <typename T, typename What>
T whole_number(const std::filesystem::path& path, const What& what, const std::string& text) {
  const std::optional<T> value = core::parse_whole_number<T>(text);
  if (!value) not_a_store(path, fmt::format("its {} is '{}', not a whole number", holder(what), text.substr(0, 40)));
  return *value;
}

// An enum the store keeps as its name, or not_a_store naming what holds another text.
template <core::NamedEnum E, typename What>
E named(const std::filesystem::path& path, const What& what, const std::string& text) {
  if (const auto value = core::enum_from_name<E>(text)) return *value;
  not_a_store(path, fmt::format("its {} is '{}', not {}", holder(what), text.substr(0, 40), core::enum_choices<E>()));
}

}  // namespace emrm::campaign::detail
