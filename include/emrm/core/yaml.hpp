#pragma once

// YAML input and output that always knows where it is: every value read through these helpers
// can name its file, line and column in an InputError. Configuration structs describe their
// fields once, in a `template <class Archive> void serialize(Archive& a)` member, and the same
// member serves reading (YamlReader), writing (YamlWriter) and validating (core::Validator,
// core/config.hpp), in the spirit of Drake's Serialize(Archive*). The readers and writers here
// ignore the constraints and rules that serialize() attaches to fields.

#include <yaml-cpp/yaml.h>

#include <array>
#include <concepts>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "emrm/core/config.hpp"
#include "emrm/core/enum_names.hpp"
#include "emrm/core/error.hpp"

namespace emrm::core {

/// A YAML node plus the name of the file it came from. Cheap to copy (shares the tree).
class YamlNode {
 public:
  YamlNode(const YAML::Node& node, std::shared_ptr<const std::string> file);
  YamlNode(const YamlNode&) = default;
  YamlNode(YamlNode&&) = default;
  /// Rebinds to the other node. (A YAML::Node assigned to would overwrite the node it refers to,
  /// inside the tree.)
  YamlNode& operator=(const YamlNode& other) {
    node_.reset(other.node_);
    file_ = other.file_;
    return *this;
  }
  YamlNode& operator=(YamlNode&& other) {  // NOLINT(performance-noexcept-move-constructor)
    node_.reset(other.node_);
    file_ = std::move(other.file_);
    return *this;
  }
  ~YamlNode() = default;

  /// Reads and parses a file. Throws InputError if it cannot be read or is not valid YAML.
  static YamlNode load_file(const std::filesystem::path& path);
  /// Parses text; `file_name` is used in messages. Throws InputError on malformed YAML.
  static YamlNode parse(const std::string& text, std::string file_name);

  [[nodiscard]] const YAML::Node& raw() const noexcept { return node_; }
  [[nodiscard]] const std::string& file() const noexcept { return *file_; }
  [[nodiscard]] SourceLocation location() const;
  /// Throws InputError at this node's location.
  [[noreturn]] void fail(const std::string& message) const;

  [[nodiscard]] bool is_map() const { return node_.IsMap(); }
  [[nodiscard]] bool is_sequence() const { return node_.IsSequence(); }
  [[nodiscard]] bool is_scalar() const { return node_.IsScalar(); }
  [[nodiscard]] bool is_null() const { return !node_.IsDefined() || node_.IsNull(); }
  /// "a mapping", "a list", "a scalar 'x'" or "nothing": for messages.
  [[nodiscard]] std::string describe() const;

  /// The value under `key` of a mapping, if present. Throws InputError if this is not a mapping.
  [[nodiscard]] std::optional<YamlNode> find(std::string_view key) const;
  /// The value under `key`; throws InputError naming the missing field at this mapping.
  [[nodiscard]] YamlNode at(std::string_view key) const;
  /// Elements of a list; throws InputError if this is not a list.
  [[nodiscard]] std::vector<YamlNode> elements() const;
  /// Keys and values of a mapping, in file order; throws InputError on a duplicate key.
  [[nodiscard]] std::vector<std::pair<YamlNode, YamlNode>> entries() const;

  /// Scalar conversions; each throws InputError saying what was expected.
  [[nodiscard]] std::string as_string() const;
  [[nodiscard]] double as_double() const;  ///< finite numbers only
  [[nodiscard]] long long as_int() const;
  [[nodiscard]] bool as_bool() const;

 private:
  YAML::Node node_;
  std::shared_ptr<const std::string> file_;
};

/// How one type is read from and written to YAML. Specialise for your own types.
template <class T, class Enable = void>
struct YamlCodec;

class YamlReader;

template <class T>
concept YamlSerializable = requires(T& value, YamlReader& reader) {
  value.serialize(reader);
};

template <class T>
inline constexpr bool kIsOptional = false;
template <class T>
inline constexpr bool kIsOptional<std::optional<T>> = true;

/// Fills a struct from one YAML mapping. Fields not visited are rejected by finish(), so a
/// misspelt key is an error and not a silently ignored default.
class YamlReader {
 public:
  static constexpr bool kReading = true;
  explicit YamlReader(YamlNode map);

  template <class T, class... Constraints>
  void required(std::string_view key, T& value, const Constraints&... /*checked by Validator*/) {
    known_.emplace_back(key);
    // The key must be there; its value may be null (none) only for an optional value.
    const auto child = node_.find(key);
    if (!child || (!kIsOptional<T> && child->is_null())) missing(key);
    YamlCodec<T>::read(*child, value);
  }
  template <class T, class... Constraints>
  void optional(std::string_view key, T& value, const Constraints&... /*checked by Validator*/) {
    known_.emplace_back(key);
    if (auto child = node_.find(key); child && !child->is_null()) YamlCodec<T>::read(*child, value);
  }
  /// A key that used to belong here: its presence is an error that says where it went.
  void moved(std::string_view key, std::string_view now_at) const;
  /// A required `key` is absent: the error is at a key of the mapping that is a misspelling of it
  /// ("unknown field 'severty' (did you mean 'severity'?)"), else at the mapping.
  [[noreturn]] void missing(std::string_view key) const;
  /// Records where the mapping being read starts.
  void location(SourceLocation& where) const { where = node_.location(); }
  /// Rules are checked by Validator once the whole configuration is read.
  template <class... Args>
  void ensure(bool /*ok*/, std::string_view /*field*/, std::string_view /*format*/, const Args&... /*args*/) const {}
  /// Throws InputError for the first key that no field claimed, listing the expected keys.
  void finish() const;
  [[nodiscard]] const YamlNode& node() const noexcept { return node_; }

 private:
  YamlNode node_;
  std::vector<std::string> known_;
};

/// Writes a struct as one YAML mapping, fields in the order serialize() visits them.
class YamlWriter {
 public:
  static constexpr bool kReading = false;
  static constexpr bool kWritesFile = true;  ///< a serialize() may leave out a field that a file need not have

  template <class T, class... Constraints>
  void required(std::string_view key, const T& value, const Constraints&... /*checked by Validator*/) {
    node_[std::string(key)] = YamlCodec<T>::write(value);
  }
  template <class T, class... Constraints>
  void optional(std::string_view key, const T& value, const Constraints&... /*checked by Validator*/) {
    node_[std::string(key)] = YamlCodec<T>::write(value);
  }
  void location(const SourceLocation& /*where*/) const {}
  template <class... Args>
  void ensure(bool /*ok*/, std::string_view /*field*/, std::string_view /*format*/, const Args&... /*args*/) const {}
  [[nodiscard]] YAML::Node node() const { return node_; }

 private:
  YAML::Node node_{YAML::NodeType::Map};
};

/// Reads a whole struct from a mapping (and rejects unknown keys).
template <YamlSerializable T>
void read_yaml(const YamlNode& node, T& value) {
  YamlReader reader(node);
  value.serialize(reader);
  reader.finish();
}

/// Writes a whole struct as a mapping.
template <class T>
[[nodiscard]] YAML::Node write_yaml(const T& value) {
  YamlWriter writer;
  const_cast<T&>(value).serialize(writer);  // serialize() only reads fields when writing
  return writer.node();
}

/// YAML text of a node, block style.
[[nodiscard]] std::string to_yaml_text(const YAML::Node& node);

/// YAML text as emrm emits it (to_yaml_text), every number written as people read it
/// (readable_number: 4.95, not 4.9500000000000002), for showing a stored configuration. Only a
/// scalar spelled as a double's shortest exact form or its 17 digits (yaml-cpp's) changes; other
/// text is kept. Text that is
/// not YAML is returned as it is.
[[nodiscard]] std::string readable_yaml(const std::string& text);

/// The node a field path names below `root`: the field's own node if the file has it, else the
/// nearest enclosing mapping or list that it has (for a default that another field made invalid).
[[nodiscard]] YamlNode node_at(const YamlNode& root, const FieldPath& path);

/// Throws InputError at node_at(root, error.path()) with the error's detail, prefixed with the
/// field path when `with_path` ("road.lane_width_m: expected a value > 0, got -1").
[[noreturn]] void fail_at(const YamlNode& root, const ConfigError& error, bool with_path);

// ---- codecs for the usual types ------------------------------------------------------------

template <>
struct YamlCodec<std::string> {
  static void read(const YamlNode& n, std::string& v) { v = n.as_string(); }
  static YAML::Node write(const std::string& v) { return YAML::Node(v); }
};
/// A number as a scalar of its shortest text that reads back the same double (1.156, not
/// 1.1559999999999999); infinities and NaN as YAML spells them.
[[nodiscard]] YAML::Node yaml_number(double v);

template <>
struct YamlCodec<double> {
  static void read(const YamlNode& n, double& v) { v = n.as_double(); }
  static YAML::Node write(double v) { return yaml_number(v); }
};
template <>
struct YamlCodec<bool> {
  static void read(const YamlNode& n, bool& v) { v = n.as_bool(); }
  static YAML::Node write(bool v) { return YAML::Node(v); }
};
template <std::integral T>
requires(!std::same_as<T, bool>) struct YamlCodec<T> {
  static void read(const YamlNode& n, T& v) {
    const long long x = n.as_int();
    if (!std::in_range<T>(x)) n.fail("integer out of range");
    v = static_cast<T>(x);
  }
  static YAML::Node write(T v) { return YAML::Node(v); }
};
template <class T>
struct YamlCodec<std::vector<T>> {
  static void read(const YamlNode& n, std::vector<T>& v) {
    v.clear();
    for (const auto& element : n.elements()) {
      T item{};
      YamlCodec<T>::read(element, item);
      v.push_back(std::move(item));
    }
  }
  static YAML::Node write(const std::vector<T>& v) {
    YAML::Node out(YAML::NodeType::Sequence);
    for (const auto& item : v) out.push_back(YamlCodec<T>::write(item));
    return out;
  }
};
/// A mapping with string keys (read in file order; a duplicate key is an error).
template <class T>
struct YamlCodec<std::map<std::string, T>> {
  static void read(const YamlNode& n, std::map<std::string, T>& v) {
    v.clear();
    for (const auto& [key, value] : n.entries()) {
      T item{};
      YamlCodec<T>::read(value, item);
      v.emplace(key.as_string(), std::move(item));
    }
  }
  static YAML::Node write(const std::map<std::string, T>& v) {
    YAML::Node out(YAML::NodeType::Map);
    for (const auto& [key, item] : v) out[key] = YamlCodec<T>::write(item);
    return out;
  }
};
/// An object with its keys in the vector's order; read in file order (a duplicate key is an error).
template <class T>
struct YamlCodec<std::vector<std::pair<std::string, T>>> {
  static void read(const YamlNode& n, std::vector<std::pair<std::string, T>>& v) {
    v.clear();
    for (const auto& [key, value] : n.entries()) {
      T item{};
      YamlCodec<T>::read(value, item);
      v.emplace_back(key.as_string(), std::move(item));
    }
  }
  static YAML::Node write(const std::vector<std::pair<std::string, T>>& v) {
    YAML::Node out(YAML::NodeType::Map);
    for (const auto& [key, item] : v) out[key] = YamlCodec<T>::write(item);
    return out;
  }
};

template <class T>
struct YamlCodec<std::optional<T>> {
  static void read(const YamlNode& n, std::optional<T>& v) {  // null: none
    if (n.is_null()) {
      v.reset();
      return;
    }
    T item{};
    YamlCodec<T>::read(n, item);
    v = std::move(item);
  }
  static YAML::Node write(const std::optional<T>& v) {
    return v ? YamlCodec<T>::write(*v) : YAML::Node(YAML::NodeType::Null);
  }
};
template <NamedEnum E>
struct YamlCodec<E> {
  static void read(const YamlNode& n, E& v) {
    const std::string text = n.as_string();
    if (auto value = enum_from_name<E>(text)) {
      v = *value;
      return;
    }
    n.fail("expected " + enum_choices<E>() + ", got '" + text + "'");
  }
  static YAML::Node write(E v) { return YAML::Node(std::string(enum_name(v))); }
};
/// A reference to another entity by id, with the place it was written (so a dangling reference
/// can be reported where it stands). Written in YAML as the bare id.
struct Ref {
  std::string id;
  SourceLocation where;
};

template <>
struct YamlCodec<Ref> {
  static void read(const YamlNode& n, Ref& v) {
    v.id = n.as_string();
    v.where = n.location();
  }
  static YAML::Node write(const Ref& v) { return YAML::Node(v.id); }
};

/// A transition of a finite state machine named by its source state, event and target state, as
/// written in an FSM file or referred to by a UCA: `{from: S3, event: execute_maneuver, to: S4}`.
struct TransitionRef {
  Ref from;
  Ref event;
  Ref to;
  SourceLocation where;

  /// "S3 -execute_maneuver-> S4"
  [[nodiscard]] std::string str() const { return from.id + " -" + event.id + "-> " + to.id; }

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("from", from);
    a.required("event", event);
    a.required("to", to);
  }
};

template <YamlSerializable T>
struct YamlCodec<T> {
  static void read(const YamlNode& n, T& v) { read_yaml(n, v); }
  static YAML::Node write(const T& v) { return write_yaml(v); }
};

}  // namespace emrm::core
