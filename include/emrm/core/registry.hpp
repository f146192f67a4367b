#pragma once

// A registry of named extension objects (strategies, planners), in the manner of esmini's
// RegisterController: built-in entries are there from the start, and a program or a test may add
// its own for as long as it needs them. Readers take a snapshot (a shared pointer to an immutable
// table), so a simulation running on another thread never sees a table change under it; adding or
// removing publishes a new table.

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/core/error.hpp"

namespace emrm::core {

template <class T>
class Registry {
 public:
  using Table = std::vector<T>;
  using NameOf = std::function<std::string_view(const T&)>;
  /// Orders the table: true when the first entry comes before the second (stable otherwise).
  using Before = std::function<bool(const T&, const T&)>;

  /// `what` names an entry in messages ("strategy", "planner").
  Registry(std::string what, Table initial, NameOf name_of, Before before = {})
      : what_(std::move(what)), name_of_(std::move(name_of)), before_(std::move(before)) {
    publish(std::move(initial));
  }

  /// The current table. Cheap (one lock and a shared pointer copy); keep it for a whole task.
  [[nodiscard]] std::shared_ptr<const Table> table() const {
    const std::lock_guard lock(mutex_);
    return table_;
  }

  /// The entries' names, in the table's order.
  [[nodiscard]] std::vector<std::string> names() const {
    const auto current = table();
    std::vector<std::string> out;
    out.reserve(current->size());
    for (const auto& e : *current) out.emplace_back(name_of_(e));
    return out;
  }

  /// Adds an entry. Throws UsageError if its name is already registered.
  void add(T entry) {
    const std::lock_guard lock(mutex_);
    const std::string_view name = name_of_(entry);
    for (const auto& e : *table_)
      if (name_of_(e) == name) throw UsageError(fmt::format("{} '{}' is already registered", what_, name));
    Table next = *table_;
    next.push_back(std::move(entry));
    publish(std::move(next));
  }

  /// Removes the entry of that name, if any.
  void remove(std::string_view name) {
    const std::lock_guard lock(mutex_);
    Table next;
    for (const auto& e : *table_)
      if (name_of_(e) != name) next.push_back(e);
    publish(std::move(next));
  }

 private:
  void publish(Table next) {
    if (before_) std::stable_sort(next.begin(), next.end(), before_);
    table_ = std::make_shared<const Table>(std::move(next));
  }

  std::string what_;
  NameOf name_of_;
  Before before_;
  mutable std::mutex mutex_;
  std::shared_ptr<const Table> table_;
};

}  // namespace emrm::core
