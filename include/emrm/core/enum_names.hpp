#pragma once

// Names of an enum's values, written once per enum (a table of value–name pairs): the YAML codec,
// the results store, the exports and the messages read and write an enum through it.

#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace emrm::core {

/// Names of an enum's values. Specialise with
/// `static constexpr std::array<std::pair<E, std::string_view>, N> kNames{...};`.
template <class E>
struct EnumNames;

template <class E>
concept NamedEnum = std::is_enum_v<E> && requires {
  EnumNames<E>::kNames;
};

/// The name of an enum value from its EnumNames table.
template <NamedEnum E>
[[nodiscard]] constexpr std::string_view enum_name(E value) noexcept {
  for (const auto& [v, name] : EnumNames<E>::kNames)
    if (v == value) return name;
  return "?";
}

/// The name of an enum value as a string (for rows, JSON and messages).
template <NamedEnum E>
[[nodiscard]] std::string enum_text(E value) {
  return std::string(enum_name(value));
}

/// The enum value of a name, if it is one.
template <NamedEnum E>
[[nodiscard]] constexpr std::optional<E> enum_from_name(std::string_view name) noexcept {
  for (const auto& [v, n] : EnumNames<E>::kNames)
    if (n == name) return v;
  return std::nullopt;
}

/// "a, b or c" of an enum's names, for messages (an empty name reads "''").
template <NamedEnum E>
[[nodiscard]] std::string enum_choices() {
  std::string out;
  const auto& names = EnumNames<E>::kNames;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += (i + 1 == names.size()) ? " or " : ", ";
    out += names[i].second.empty() ? std::string_view("''") : names[i].second;
  }
  return out;
}

/// The names of an enum's values, in the table's order.
template <NamedEnum E>
[[nodiscard]] std::vector<std::string> enum_names() {
  std::vector<std::string> out;
  for (const auto& [v, name] : EnumNames<E>::kNames) out.emplace_back(name);
  return out;
}

}  // namespace emrm::core
