#include "emrm/core/config.hpp"

#include <fmt/args.h>
#include <fmt/format.h>

#include <algorithm>

#include "emrm/core/text.hpp"

namespace emrm::core {

std::string format_value(double value) { return fmt::format("{}", value); }
std::string format_value(long long value) { return fmt::format("{}", value); }

std::string format_message(std::string_view format, std::initializer_list<MessageArg> args) {
  fmt::dynamic_format_arg_store<fmt::format_context> store;
  for (const MessageArg& arg : args) std::visit([&store](const auto& value) { store.push_back(value); }, arg.value());
  return fmt::vformat(format, store);
}

std::string expected_got(std::string_view what, double value) {
  return fmt::format("expected {}, got {}", what, value);
}
std::string expected_got(std::string_view what, long long value) {
  return fmt::format("expected {}, got {}", what, value);
}

std::string Within::message(double v) const { return expected_got(fmt::format("a value in [{}, {}]", low, high), v); }

std::string Plausible::message(double v) const {
  // A unit's slip scales a value: a negative or zero one is no slip.
  const std::string_view slip = v > 0.0 && v < low ? below : (v > high ? above : std::string_view());
  return expected_got(fmt::format("{} in [{:g}, {:g}] {} for a road vehicle", what, low, high, unit), v) +
         (slip.empty() ? std::string() : fmt::format(" ({})", slip));
}

std::string OpenInterval::message(double v) const { return expected_got(fmt::format("a value in {}", text), v); }

std::string AtLeast::message(long long v) const {
  return expected_got(fmt::format("at least {} {}", minimum, noun), v);
}

bool OneOf::holds(const std::string& v) const {
  const std::vector<std::string> allowed = names();
  return std::find(allowed.begin(), allowed.end(), v) != allowed.end();
}

std::string OneOf::message(const std::string& v) const {
  return fmt::format("unknown {} '{}'{}; expected one of: {}", what, v, did_you_mean(v, names()), join(names(), ", "));
}

std::string FieldPath::str() const {
  std::string out;
  for (const Step& step : steps) {
    if (const auto* key = std::get_if<std::string>(&step)) {
      if (!out.empty()) out += '.';
      out += *key;
    } else {
      out += fmt::format("[{}]", std::get<std::size_t>(step));
    }
  }
  return out;
}

namespace {

std::string config_message(std::string_view subject, const FieldPath& path, const std::string& detail) {
  const std::string where = path.str();
  return where.empty() ? fmt::format("{}: {}", subject, detail) : fmt::format("{}: {}: {}", subject, where, detail);
}

}  // namespace

ConfigError::ConfigError(std::string_view subject, FieldPath path, std::string detail)
    : InputError({}, config_message(subject, path, detail)), path_(std::move(path)), detail_(std::move(detail)) {}

void Validator::fail(std::string_view field, std::string detail) const {
  FieldPath path;
  for (const auto& step : path_) {
    if (const auto* key = std::get_if<std::string_view>(&step))
      path.steps.emplace_back(std::string(*key));
    else
      path.steps.emplace_back(std::get<std::size_t>(step));
  }
  // A dotted field names a path below the current one: "road.ego_lane_center_m".
  while (!field.empty()) {
    const auto dot = field.find('.');
    path.steps.emplace_back(std::string(field.substr(0, dot)));
    field = dot == std::string_view::npos ? std::string_view() : field.substr(dot + 1);
  }
  throw ConfigError(subject_, std::move(path), std::move(detail));
}

}  // namespace emrm::core
