#pragma once

// Constraints on configuration fields, written where the field is described: in the struct's
// `template <class Archive> void serialize(Archive& a)` member, next to its name.
//
//   EMRM_FIELD(a, lane_width_m, core::positive);  // a.optional("lane_width_m", lane_width_m, core::positive)
//   a.ensure(dt_s <= horizon_s, "dt_s", "expected a time step no longer than the horizon ({} s), got {} s",
//            horizon_s, dt_s);
//
// The reading and writing archives (YamlReader, YamlWriter in core/yaml.hpp) ignore constraints
// and rules; the Validator below checks them all, so a configuration built in code is held to the
// same rules as one loaded from a file. This header needs no YAML library: a header that only
// declares serialize() members includes this one, not core/yaml.hpp.

#include <concepts>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "emrm/core/error.hpp"

/// `a.optional("field", field, constraints...)` with the field's name written once.
#define EMRM_FIELD(archive, field, ...) (archive).optional(#field, field __VA_OPT__(, ) __VA_ARGS__)
/// `a.required("field", field, constraints...)` with the field's name written once.
#define EMRM_REQUIRED_FIELD(archive, field, ...) (archive).required(#field, field __VA_OPT__(, ) __VA_ARGS__)
/// EMRM_FIELD, but left out of a file written while the field holds `default_value`: a field added
/// after stores and configuration hashes were written keeps them valid (core::field_unless_default).
#define EMRM_FIELD_UNLESS_DEFAULT(archive, field, default_value, ...) \
  ::emrm::core::field_unless_default(archive, #field, field, default_value __VA_OPT__(, ) __VA_ARGS__)

namespace emrm::core {

/// Whether the archive `A` writes a file (YamlWriter): a serialize() may then leave out a field that
/// the file need not have (one at its default, a block another family reads).
template <class A>
inline constexpr bool writes_file = requires {
  A::kWritesFile;
};

/// `a.optional(key, field, constraints...)`, except when `A` writes a file and the field holds
/// `default_value` (EMRM_FIELD_UNLESS_DEFAULT).
template <class A, class T, class... Constraints>
void field_unless_default(A& a, std::string_view key, T& field, const T& default_value,
                          const Constraints&... constraints) {
  if (!writes_file<A> || field != default_value) a.optional(key, field, constraints...);
}

// ---- formatting values for messages --------------------------------------------------------

/// A value as messages show it: fmt's "{}" (the shortest text that reads back as the same double).
[[nodiscard]] std::string format_value(double value);
[[nodiscard]] std::string format_value(long long value);

/// One argument of a rule's message.
class MessageArg {
 public:
  MessageArg(double value) : value_(value) {}  // NOLINT(google-explicit-constructor)
  template <std::integral I>
  requires(!std::same_as<I, bool>) MessageArg(I value) {  // NOLINT(google-explicit-constructor)
    if constexpr (std::is_signed_v<I>)
      value_ = static_cast<long long>(value);
    else
      value_ = static_cast<unsigned long long>(value);
  }
  MessageArg(std::string_view value) : value_(std::string(value)) {}  // NOLINT(google-explicit-constructor)
  MessageArg(const std::string& value) : value_(value) {}             // NOLINT(google-explicit-constructor)
  MessageArg(const char* value) : value_(std::string(value)) {}       // NOLINT(google-explicit-constructor)

  using Value = std::variant<double, long long, unsigned long long, std::string>;
  [[nodiscard]] const Value& value() const noexcept { return value_; }

 private:
  Value value_;
};

/// `format` (fmt syntax: "{}", "{:g}") filled with `args`.
[[nodiscard]] std::string format_message(std::string_view format, std::initializer_list<MessageArg> args);

// ---- constraints ---------------------------------------------------------------------------
// Each has holds(value) and message(value): what a failing value is told ("expected a value > 0,
// got -1"). Messages are built only when a value fails.

/// "expected <what>, got <value>".
[[nodiscard]] std::string expected_got(std::string_view what, double value);
[[nodiscard]] std::string expected_got(std::string_view what, long long value);

struct Positive {
  [[nodiscard]] bool holds(double v) const noexcept { return v > 0.0; }
  [[nodiscard]] std::string message(double v) const { return expected_got("a value > 0", v); }
};
/// The value is > 0 (NaN fails).
inline constexpr Positive positive{};

struct NonNegative {
  [[nodiscard]] bool holds(double v) const noexcept { return v >= 0.0; }
  [[nodiscard]] std::string message(double v) const { return expected_got("a value >= 0", v); }
};
/// The value is >= 0 (NaN fails).
inline constexpr NonNegative non_negative{};

struct Within {
  double low = 0.0;
  double high = 0.0;
  [[nodiscard]] bool holds(double v) const noexcept { return v >= low && v <= high; }
  [[nodiscard]] std::string message(double v) const;
};
/// The value lies in the closed interval [low, high].
[[nodiscard]] constexpr Within within(double low, double high) noexcept { return {low, high}; }

/// A quantity of a road vehicle: outside [low, high] (in `unit`) no road vehicle has it, and the
/// likely slip is a unit, which the message names: "expected a mass in [300, 60000] kg for a road
/// vehicle, got 2 (in tonnes?)". NaN fails.
struct Plausible {
  double low = 0.0;
  double high = 0.0;
  std::string_view what;   ///< "a mass"
  std::string_view unit;   ///< "kg"
  std::string_view below;  ///< the slip behind a value below `low`: "in tonnes?" ("" for none)
  std::string_view above;  ///< and above `high`: "in grams?"
  [[nodiscard]] bool holds(double v) const noexcept { return v >= low && v <= high; }
  [[nodiscard]] std::string message(double v) const;
};
[[nodiscard]] constexpr Plausible plausible(double low, double high, std::string_view what, std::string_view unit,
                                            std::string_view below, std::string_view above) noexcept {
  return {low, high, what, unit, below, above};
}

struct OpenInterval {
  double low = 0.0;
  double high = 0.0;
  std::string_view text;  ///< how messages write the interval: "(0, pi/2)"
  [[nodiscard]] bool holds(double v) const noexcept { return v > low && v < high; }
  [[nodiscard]] std::string message(double v) const;
};
/// The value lies in the open interval (low, high); `text` writes it for messages.
[[nodiscard]] constexpr OpenInterval open_interval(double low, double high, std::string_view text) noexcept {
  return {low, high, text};
}

struct Probability {
  [[nodiscard]] bool holds(double v) const noexcept { return v > 0.0 && v <= 1.0; }
  [[nodiscard]] std::string message(double v) const { return expected_got("a probability in (0, 1]", v); }
};
/// The value is a probability in (0, 1] (a threshold that zero would make always true).
inline constexpr Probability probability{};

struct AtLeast {
  long long minimum = 0;
  std::string_view noun;  ///< what is counted: "lane" reads "expected at least 1 lane, got 0"
  [[nodiscard]] bool holds(long long v) const noexcept { return v >= minimum; }
  [[nodiscard]] std::string message(long long v) const;
};
/// An integer count of at least `minimum` `noun`s.
[[nodiscard]] constexpr AtLeast at_least(long long minimum, std::string_view noun) noexcept { return {minimum, noun}; }

struct OneOf {
  std::vector<std::string> (*names)() = nullptr;  ///< the names allowed, asked when checking
  std::string_view what;                          ///< "vehicle model"
  [[nodiscard]] bool holds(const std::string& v) const;
  [[nodiscard]] std::string message(const std::string& v) const;
};
/// A name from a list that `names()` provides (a registry's): "unknown vehicle model 'x'; expected
/// one of: a, b".
[[nodiscard]] constexpr OneOf one_of(std::vector<std::string> (*names)(), std::string_view what) noexcept {
  return {names, what};
}

// ---- field paths and the error ---------------------------------------------------------------

/// Where a field lies in a configuration: mapping keys and list indices, outermost first.
struct FieldPath {
  using Step = std::variant<std::string, std::size_t>;
  std::vector<Step> steps;

  /// "road.lane_width_m", "grids[1].name", "strategies[0]"; empty for the whole configuration.
  [[nodiscard]] std::string str() const;
};

/// A configuration that breaks a constraint or a rule, found by Validator. An InputError without a
/// file position: message() reads "SUBJECT: PATH: DETAIL" ("scene: road.lane_width_m: expected a
/// value > 0, got -1"). Loaders catch it and report DETAIL at the field's place in the file.
class ConfigError : public InputError {
 public:
  ConfigError(std::string_view subject, FieldPath path, std::string detail);

  [[nodiscard]] const FieldPath& path() const noexcept { return path_; }
  /// What is wrong, without the subject and the path.
  [[nodiscard]] const std::string& detail() const noexcept { return detail_; }

 private:
  FieldPath path_;
  std::string detail_;
};

// ---- the validating archive ------------------------------------------------------------------

/// Walks serialize() (or is called by a hand-written validate()) and throws ConfigError at the
/// first field whose value breaks a constraint or rule. Builds no message or path while values pass.
class Validator {
 public:
  static constexpr bool kReading = false;

  /// `subject` names the configuration in messages: "scene", "campaign", "odd".
  explicit Validator(std::string subject) : subject_(std::move(subject)) { path_.reserve(8); }

  template <class T, class... Constraints>
  void required(std::string_view key, const T& value, const Constraints&... constraints) {
    field(key, value, constraints...);
  }
  template <class T, class... Constraints>
  void optional(std::string_view key, const T& value, const Constraints&... constraints) {
    field(key, value, constraints...);
  }
  void location(const SourceLocation& /*where*/) const noexcept {}

  /// A rule across fields: when `ok` is false, fails at `field` (a key of the struct being
  /// visited, or a dotted path below it: "road.ego_lane_center_m") with `format` filled with `args`.
  template <class... Args>
  void ensure(bool ok, std::string_view field, std::string_view format, const Args&... args) {
    if (!ok) fail(field, format_message(format, {MessageArg(args)...}));
  }

  /// Checks `value` at `key` below the current path: a struct with serialize() is walked, a list
  /// of them element by element; anything else is checked against `constraints`.
  template <class T, class... Constraints>
  void field(std::string_view key, const T& value, const Constraints&... constraints) {
    path_.emplace_back(key);
    visit(value, constraints...);
    path_.pop_back();
  }

  /// Enters a key or a list element of the current path for as long as it lives.
  class Scope {
   public:
    Scope(Validator& v, std::string_view key) : v_(v) { v_.path_.emplace_back(key); }
    Scope(Validator& v, std::size_t index) : v_(v) { v_.path_.emplace_back(index); }
    ~Scope() { v_.path_.pop_back(); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    Validator& v_;
  };

  /// Throws ConfigError at `field` below the current path (empty: the current path itself).
  [[noreturn]] void fail(std::string_view field, std::string detail) const;

 private:
  template <class T, class... Constraints>
  void visit(const T& value, const Constraints&... constraints) {
    if constexpr (requires(T & t, Validator & v) { t.serialize(v); }) {
      static_assert(sizeof...(Constraints) == 0, "constraints apply to values, not to structs");
      const_cast<T&>(value).serialize(*this);  // serialize() only reads fields when not reading
    } else if constexpr (requires(T & list, Validator & v) {
                           list.size();
                           list[0].serialize(v);
                         }) {
      for (std::size_t i = 0; i < value.size(); ++i) {
        path_.emplace_back(i);
        visit(value[i], constraints...);
        path_.pop_back();
      }
    } else {
      (check(value, constraints), ...);
    }
  }

  template <class T, class C>
  void check(const T& value, const C& constraint) const {
    if (!constraint.holds(value)) fail({}, constraint.message(value));
  }

  std::string subject_;
  std::vector<std::variant<std::string_view, std::size_t>> path_;
};

/// Checks every constraint and rule of `config.serialize()`; throws ConfigError naming `subject`
/// and the field path at the first that fails.
template <class T>
void validate_fields(std::string subject, const T& config) {
  Validator v(std::move(subject));
  const_cast<T&>(config).serialize(v);  // serialize() only reads fields when not reading
}

}  // namespace emrm::core
