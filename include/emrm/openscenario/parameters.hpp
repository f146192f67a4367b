#pragma once

// OpenSCENARIO parameters (ParameterDeclarations, `$name` references and 1.1+ `${...}`
// expressions) as one scope per declaring element: the scenario's global scope, and a scope per
// catalog entry whose parent is the scope the reference was read in.

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/error.hpp"

namespace emrm::openscenario {

/// The parameter types of OpenSCENARIO 1.0-1.3 (ParameterType); dateTime is kept as its text.
enum class ParameterType { kDouble, kInt, kUnsignedInt, kUnsignedShort, kString, kBoolean, kDateTime };

/// The XSD spelling ("double", "unsignedShort", ...).
[[nodiscard]] std::string_view type_name(ParameterType type) noexcept;
/// The type a spelling names; throws InputError at `where` when there is none.
[[nodiscard]] ParameterType parse_type(std::string_view name, const SourceLocation& where);
/// The text without the spaces around it.
[[nodiscard]] std::string_view trim_spaces(std::string_view text) noexcept;
/// A finite number written as the whole text, spaces around it allowed; none otherwise.
[[nodiscard]] std::optional<double> parse_number(std::string_view text);
/// The parameter names `text` refers to, in order: each `$name`, also inside `${...}`.
[[nodiscard]] std::vector<std::string_view> parameter_references(std::string_view text);

/// Whether parameters of the type are numbers (double, int, unsignedInt, unsignedShort): those a
/// scene may make factors.
[[nodiscard]] bool numeric(ParameterType type) noexcept;

/// Values from outside (the factors of a cell), by parameter name: numbers or texts. An override
/// replaces the declared default before anything refers to it.
using ParameterOverrides = std::map<std::string, std::string>;
[[nodiscard]] ParameterOverrides overrides_from(const std::map<std::string, double>& values);

/// One declared parameter: its type, its value (resolved: references and expressions evaluated)
/// and where it was declared.
struct Parameter {
  std::string name;
  ParameterType type = ParameterType::kString;
  std::string default_text;  ///< as declared, before overrides and evaluation
  std::string value;         ///< resolved
  SourceLocation where;
};

/// The parameters visible in one element. Borrowing `parent` (it must outlive this scope).
class ParameterScope {
 public:
  explicit ParameterScope(const ParameterScope* parent = nullptr) : parent_(parent) {}

  /// Declares `name` with `value_text` (which may refer to parameters declared before it, in this
  /// scope or its parents), replaced by `overrides[name]` when there is one. A name declared again
  /// in the same scope takes the later declaration (esmini's rule). Throws InputError at `where` for
  /// a value that is not of `type`.
  void declare(const std::string& name, ParameterType type, const std::string& value_text, const SourceLocation& where,
               const ParameterOverrides& overrides = {});

  /// The parameter `name` here or in a parent, or nullptr.
  [[nodiscard]] const Parameter* find(std::string_view name) const;

  /// An attribute's text with a leading `$name` replaced by the parameter's value and `${...}`
  /// evaluated; other text is returned as it is. `where` is the position of the text's first
  /// character: an error names the column of the offending token.
  [[nodiscard]] std::string resolve(std::string_view text, const SourceLocation& where) const;

  /// This scope's own declarations, in order.
  [[nodiscard]] const std::vector<Parameter>& declared() const noexcept { return declared_; }

 private:
  const ParameterScope* parent_;
  std::vector<Parameter> declared_;
};

/// Evaluates the inside of `${...}` (without the braces): numbers, `$name` references, + - * / %,
/// unary minus, parentheses, comparisons (< <= > >= == !=), not/and/or (booleans as 1 and 0),
/// true/false, and round floor ceil sqrt pow abs sign min max exp log sin cos tan asin acos atan.
/// `where` is the position of the text's first character. Throws InputError at the offending
/// column for a syntax error, an unknown name or function, a non-numeric parameter, a division by
/// zero or a result that is not finite.
[[nodiscard]] double evaluate_expression(std::string_view text, const ParameterScope& scope,
                                         const SourceLocation& where);

/// A number as parameters carry it: integers without a fraction, others with enough digits to
/// read back the same double.
[[nodiscard]] std::string format_number(double value);

}  // namespace emrm::openscenario
