#pragma once

// JSON output through the same serialize() member that reads a struct from YAML: a result file
// that emrm writes as JSON lists its fields once, for its writer (JsonWriter, here) and its typed
// reader (read_json_file: YamlReader over the file, since JSON is YAML, so that every error names
// the file, line and column). The twin of YamlWriter (core/yaml.hpp), with these rules:
//   - members in the order serialize() visits them;
//   - an empty std::optional is null under required() and left out under optional();
//   - a std::vector<std::pair<std::string, T>> is an object with its keys in the vector's order
//     (YamlCodec reads it back in file order).

#include <concepts>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "emrm/core/enum_names.hpp"
#include "emrm/core/yaml.hpp"

namespace emrm::core {

/// How one type is written as JSON. Specialise for your own types.
template <class T, class Enable = void>
struct JsonCodec;

/// Writes a struct as one JSON object, members in the order serialize() visits them.
class JsonWriter {
 public:
  static constexpr bool kReading = false;

  template <class T, class... Constraints>
  void required(std::string_view key, const T& value, const Constraints&... /*checked by Validator*/) {
    object_[std::string(key)] = JsonCodec<T>::write(value);
  }
  template <class T, class... Constraints>
  void optional(std::string_view key, const T& value, const Constraints&... /*checked by Validator*/) {
    if constexpr (requires { value.has_value(); }) {
      if (!value.has_value()) return;
    }
    object_[std::string(key)] = JsonCodec<T>::write(value);
  }
  void location(const SourceLocation& /*where*/) const {}
  template <class... Args>
  void ensure(bool /*ok*/, std::string_view /*field*/, std::string_view /*format*/, const Args&... /*args*/) const {}
  [[nodiscard]] nlohmann::ordered_json object() && { return std::move(object_); }

 private:
  nlohmann::ordered_json object_ = nlohmann::ordered_json::object();
};

/// Writes a whole struct as a JSON object.
template <class T>
[[nodiscard]] nlohmann::ordered_json write_json(const T& value) {
  JsonWriter writer;
  const_cast<T&>(value).serialize(writer);  // serialize() only reads fields when writing
  return std::move(writer).object();
}

/// Parses a JSON file as YAML (a superset), its syntax errors said as JSON's: "not valid JSON: ...".
[[nodiscard]] YamlNode load_json_file(const std::filesystem::path& path);

/// Reads a value from a JSON file that its writer wrote: a struct from an object with its members
/// (write_json), or a list of them. Throws InputError naming the file, line and column of what is
/// missing, misspelt or of the wrong type.
template <class T>
[[nodiscard]] T read_json_file(const std::filesystem::path& path) {
  const YamlNode root = load_json_file(path);
  if constexpr (YamlSerializable<T>) {
    if (!root.is_map()) root.fail("expected a JSON object, got " + root.describe());
  }
  T value{};
  YamlCodec<T>::read(root, value);
  return value;
}

// ---- codecs for the usual types ------------------------------------------------------------

template <class T>
requires(std::is_arithmetic_v<T> || std::is_same_v<T, std::string>) struct JsonCodec<T> {
  static nlohmann::ordered_json write(const T& v) { return v; }
};
template <NamedEnum E>
struct JsonCodec<E> {
  static nlohmann::ordered_json write(E v) { return std::string(enum_name(v)); }
};
template <class T>
struct JsonCodec<std::optional<T>> {
  static nlohmann::ordered_json write(const std::optional<T>& v) {
    return v ? JsonCodec<T>::write(*v) : nlohmann::ordered_json(nullptr);
  }
};
template <class T>
struct JsonCodec<std::vector<T>> {
  static nlohmann::ordered_json write(const std::vector<T>& v) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const auto& item : v) out.push_back(JsonCodec<T>::write(item));
    return out;
  }
};
template <class T>
struct JsonCodec<std::vector<std::pair<std::string, T>>> {
  static nlohmann::ordered_json write(const std::vector<std::pair<std::string, T>>& v) {
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    for (const auto& [key, item] : v) out[key] = JsonCodec<T>::write(item);
    return out;
  }
};
template <YamlSerializable T>
struct JsonCodec<T> {
  static nlohmann::ordered_json write(const T& v) { return write_json(v); }
};

}  // namespace emrm::core
