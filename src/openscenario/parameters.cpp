// Parameter declarations, references and their values (parameters.hpp).

#include "emrm/openscenario/parameters.hpp"

#include <fmt/format.h>

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <utility>

namespace emrm::openscenario {
namespace {

constexpr std::array<std::pair<ParameterType, std::string_view>, 7> kTypeNames = {{
    {ParameterType::kDouble, "double"},
    {ParameterType::kInt, "int"},
    {ParameterType::kUnsignedInt, "unsignedInt"},
    {ParameterType::kUnsignedShort, "unsignedShort"},
    {ParameterType::kString, "string"},
    {ParameterType::kBoolean, "boolean"},
    {ParameterType::kDateTime, "dateTime"},
}};

bool parses_as_double(const std::string& text, double& value) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && end == text.data() + text.size() && std::isfinite(value);
}

[[noreturn]] void type_error(const std::string& name, ParameterType type, const std::string& value,
                             const SourceLocation& where, std::string_view expected) {
  throw InputError(
      where, fmt::format("parameter '{}' of type {}: expected {}, got '{}'", name, type_name(type), expected, value));
}

// The value in its type's canonical form, or an InputError.
std::string typed_value(const std::string& name, ParameterType type, const std::string& value,
                        const SourceLocation& where) {
  const auto fail = [&](std::string_view expected) { type_error(name, type, value, where, expected); };
  double number = 0.0;
  switch (type) {
    case ParameterType::kDouble:
      if (!parses_as_double(value, number)) fail("a number");
      return value;
    case ParameterType::kInt:
    case ParameterType::kUnsignedInt:
    case ParameterType::kUnsignedShort: {
      if (!parses_as_double(value, number) || number != std::round(number)) fail("an integer");
      const double low = type == ParameterType::kInt ? -2147483648.0 : 0.0;
      const double high = type == ParameterType::kInt           ? 2147483647.0
                          : type == ParameterType::kUnsignedInt ? 4294967295.0
                                                                : 65535.0;
      if (number < low || number > high) fail(fmt::format("an integer in [{}, {}]", low, high));
      return format_number(number);
    }
    case ParameterType::kBoolean:
      if (value == "true" || value == "1") return "true";
      if (value == "false" || value == "0") return "false";
      type_error(name, type, value, where, "true or false");
    case ParameterType::kString:
    case ParameterType::kDateTime:
      return value;
  }
  return value;
}

}  // namespace

std::string_view type_name(ParameterType type) noexcept {
  for (const auto& [t, name] : kTypeNames)
    if (t == type) return name;
  return "string";
}

std::string_view trim_spaces(std::string_view text) noexcept {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  return text;
}

std::optional<double> parse_number(std::string_view text) {
  text = trim_spaces(text);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::vector<std::string_view> parameter_references(std::string_view text) {
  const auto identifier = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; };
  std::vector<std::string_view> out;
  for (std::size_t i = text.find('$'); i != std::string_view::npos; i = text.find('$', i + 1)) {
    std::size_t end = i + 1;
    while (end < text.size() && identifier(text[end])) ++end;
    if (end > i + 1) out.push_back(text.substr(i + 1, end - i - 1));
  }
  return out;
}

bool numeric(ParameterType type) noexcept {
  return type == ParameterType::kDouble || type == ParameterType::kInt || type == ParameterType::kUnsignedInt ||
         type == ParameterType::kUnsignedShort;
}

ParameterType parse_type(std::string_view name, const SourceLocation& where) {
  for (const auto& [t, spelled] : kTypeNames)
    if (spelled == name) return t;
  // OpenSCENARIO 1.0 spells the integer type "integer".
  if (name == "integer") return ParameterType::kInt;
  throw InputError(where, fmt::format("unknown parameter type '{}'; expected double, int, unsignedInt, "
                                      "unsignedShort, string, boolean or dateTime",
                                      name));
}

ParameterOverrides overrides_from(const std::map<std::string, double>& values) {
  ParameterOverrides overrides;
  for (const auto& [name, value] : values) overrides[name] = format_number(value);
  return overrides;
}

std::string format_number(double value) {
  if (value == std::round(value) && std::fabs(value) < 1e15) return fmt::format("{}", static_cast<long long>(value));
  return fmt::format("{}", value);
}

void ParameterScope::declare(const std::string& name, ParameterType type, const std::string& value_text,
                             const SourceLocation& where, const ParameterOverrides& overrides) {
  const auto overridden = overrides.find(name);
  const std::string& text = overridden != overrides.end() ? overridden->second : value_text;
  std::string value = resolve(text, where);
  // A number computed for an integer type is an integer (an expression's 2*1.5 gives "3").
  double number = 0.0;
  if (type != ParameterType::kString && type != ParameterType::kDateTime && type != ParameterType::kDouble &&
      type != ParameterType::kBoolean && parses_as_double(value, number))
    value = format_number(number);
  Parameter parameter{name, type, value_text, typed_value(name, type, value, where), where};
  // A name declared again in the same scope takes the later declaration, as esmini does.
  for (auto& p : declared_)
    if (p.name == name) {
      p = std::move(parameter);
      return;
    }
  declared_.push_back(std::move(parameter));
}

const Parameter* ParameterScope::find(std::string_view name) const {
  for (const auto& p : declared_)
    if (p.name == name) return &p;
  return parent_ != nullptr ? parent_->find(name) : nullptr;
}

std::string ParameterScope::resolve(std::string_view text, const SourceLocation& where) const {
  if (text.size() >= 2 && text.starts_with("${")) {
    if (!text.ends_with("}")) throw InputError(where, fmt::format("expression '{}': expected a closing '}}'", text));
    SourceLocation inner = where;
    if (inner.column > 0) inner.column += 2;
    return format_number(evaluate_expression(text.substr(2, text.size() - 3), *this, inner));
  }
  if (text.starts_with("$")) {
    const Parameter* parameter = find(text.substr(1));
    if (parameter == nullptr) throw InputError(where, fmt::format("unknown parameter '{}'", text.substr(1)));
    return parameter->value;
  }
  return std::string(text);
}

}  // namespace emrm::openscenario
