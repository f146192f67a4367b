// The reader's attribute readers and parameter declarations (read_context.hpp).

#include "read_context.hpp"

#include <fmt/format.h>

#include <cmath>

#include "emrm/openscenario/supported.hpp"

namespace emrm::openscenario::detail {
namespace {

// Where an attribute's value starts: after name=" (the XML reader gives the name's position).
SourceLocation value_location(const xml::Element& e, std::string_view name) {
  SourceLocation at = e.where(name);
  if (at.column > 0 && e.attribute(name)) at.column += static_cast<int>(name.size()) + 2;
  return at;
}

}  // namespace

std::optional<std::string> ReadContext::optional_text(const xml::Element& e, std::string_view name) const {
  const auto raw = e.attribute(name);
  if (!raw) return std::nullopt;
  if (uses_ != nullptr) record_references(*raw, value_location(e, name));
  return scope_.resolve(*raw, value_location(e, name));
}

void ReadContext::record_references(std::string_view text, const SourceLocation& where) const {
  for (const std::string_view parameter : parameter_references(text)) {
    const Parameter* p = scope_.find(parameter);
    if (p != nullptr && p == global_->find(parameter)) uses_->push_back({std::string(parameter), "", where});
  }
}

std::optional<std::string> ReadContext::parameter_of(const xml::Element& e, std::string_view name) const {
  const auto raw = e.attribute(name);
  if (!raw || global_ == nullptr) return std::nullopt;
  const std::string_view text = trim_spaces(*raw);
  if (text.size() < 2 || text.front() != '$' || text[1] == '{') return std::nullopt;
  const std::string_view parameter = text.substr(1);
  const Parameter* p = scope_.find(parameter);
  if (p == nullptr || p != global_->find(parameter)) return std::nullopt;
  return std::string(parameter);
}

std::string ReadContext::text(const xml::Element& e, std::string_view name) const {
  if (!e.attribute(name)) e.fail(fmt::format("<{}> needs the attribute {}", e.name(), name));
  return *optional_text(e, name);
}

std::optional<double> ReadContext::optional_number(const xml::Element& e, std::string_view name, std::string_view unit,
                                                   double low, double high) const {
  const auto value = optional_text(e, name);
  if (!value) return std::nullopt;
  const std::optional<double> parsed = parse_number(*value);
  if (!parsed)
    e.fail(name, fmt::format("{}: expected a number{}, got '{}'", name, unit.empty() ? "" : fmt::format(" ({})", unit),
                             *value));
  const double number = *parsed;
  if (number < low || number > high)
    e.fail(name, fmt::format("{}: expected a value in [{}, {}]{}, got {}", name, low, high,
                             unit.empty() ? "" : fmt::format(" {}", unit), number));
  if (uses_ != nullptr)
    if (auto parameter = parameter_of(e, name))
      uses_->push_back({std::move(*parameter), std::string(unit), value_location(e, name)});
  return number;
}

double ReadContext::number(const xml::Element& e, std::string_view name, std::string_view unit, double low,
                           double high) const {
  if (!e.attribute(name)) e.fail(fmt::format("<{}> needs the attribute {}", e.name(), name));
  return *optional_number(e, name, unit, low, high);
}

int ReadContext::integer(const xml::Element& e, std::string_view name, int low, int high) const {
  const double value = number(e, name, "", low, high);
  if (value != std::round(value)) e.fail(name, fmt::format("{}: expected an integer, got {}", name, value));
  return static_cast<int>(value);
}

bool ReadContext::boolean(const xml::Element& e, std::string_view name, bool fallback) const {
  const auto value = optional_text(e, name);
  if (!value) return fallback;
  if (*value == "true" || *value == "1") return true;
  if (*value == "false" || *value == "0") return false;
  e.fail(name, fmt::format("{}: expected true or false, got '{}'", name, *value));
}

std::size_t ReadContext::choice(const xml::Element& e, std::string_view name,
                                std::initializer_list<std::string_view> names) const {
  const std::string value = text(e, name);
  std::size_t i = 0;
  std::string list;
  for (const auto n : names) {
    if (n == value) return i;
    list += (list.empty() ? "" : ", ") + std::string(n);
    ++i;
  }
  e.fail(name, fmt::format("{}: expected one of {}, got '{}'", name, list, value));
}

std::string ReadContext::entity_ref(const xml::Element& e, std::string_view name) const {
  std::string ref = text(e, name);
  if (!entities_.contains(ref)) {
    std::string known;
    for (const auto& n : entities_) known += (known.empty() ? "" : ", ") + n;
    e.fail(name, fmt::format("{}: no entity named '{}' (entities: {})", name, ref, known));
  }
  return ref;
}

xml::Element ReadContext::chosen(const xml::Element& e, std::string_view choice) const {
  const auto children = e.children();
  if (children.empty()) e.fail(fmt::format("<{}> needs a child element", e.name()));
  const xml::Element& child = children.front();
  require_supported(choice, child.name(), child.where());
  return child;
}

void declare_parameters(const xml::Element& parent, ParameterScope& scope, const ReadContext& context,
                        const ParameterOverrides& overrides) {
  (void)context;
  const auto declarations = parent.child("ParameterDeclarations");
  if (!declarations) return;
  for (const xml::Element& p : declarations->children("ParameterDeclaration")) {
    const ParameterType type = parse_type(p.required("parameterType"), p.where("parameterType"));
    SourceLocation value_at = p.where("value");
    if (value_at.column > 0 && p.attribute("value")) value_at.column += 7;
    // The value is resolved in the scope it is declared in (earlier declarations, then parents).
    const std::string raw = p.attribute("value").value_or("");
    if (!p.attribute("value")) p.fail("<ParameterDeclaration> needs the attribute value");
    scope.declare(p.required("name"), type, raw, value_at, overrides);
  }
}

}  // namespace emrm::openscenario::detail
