// OpenSCENARIO 1.1+ expressions `${...}` (parameters.hpp): a recursive-descent evaluator of the
// standard's grammar. muparser (core/expression.hpp) lacks %, pow() and the words not/and/or, and
// rewriting the text for it would move every error's column, so the grammar is read here.

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <functional>
#include <map>

#include "emrm/openscenario/parameters.hpp"

namespace emrm::openscenario {
namespace {

class Evaluator {
 public:
  Evaluator(std::string_view text, const ParameterScope& scope, const SourceLocation& where)
      : text_(text), scope_(scope), where_(where) {}

  double run() {
    const double value = or_expression();
    skip_space();
    if (pos_ < text_.size()) fail(pos_, fmt::format("unexpected '{}'", text_[pos_]));
    if (!std::isfinite(value)) fail(0, "the value is not a finite number");
    return value;
  }

 private:
  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    SourceLocation location = where_;
    if (location.column > 0) location.column += static_cast<int>(at);
    throw InputError(location, fmt::format("expression '{}': {}", text_, what));
  }

  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }

  bool take(std::string_view token) {
    skip_space();
    if (text_.substr(pos_, token.size()) != token) return false;
    // A word operator is a whole word: `order` is not `or` followed by `der`.
    if (std::isalpha(static_cast<unsigned char>(token.front())) && pos_ + token.size() < text_.size()) {
      const auto next = static_cast<unsigned char>(text_[pos_ + token.size()]);
      if (std::isalnum(next) || next == '_') return false;
    }
    pos_ += token.size();
    return true;
  }

  double or_expression() {
    double value = and_expression();
    while (take("or")) {
      const double rhs = and_expression();
      value = (value != 0.0 || rhs != 0.0) ? 1.0 : 0.0;
    }
    return value;
  }

  double and_expression() {
    double value = not_expression();
    while (take("and")) {
      const double rhs = not_expression();
      value = (value != 0.0 && rhs != 0.0) ? 1.0 : 0.0;
    }
    return value;
  }

  double not_expression() {
    int nots = 0;  // a run of `not`s, counted instead of recursed into
    while (take("not")) ++nots;
    const double value = comparison();
    if (nots == 0) return value;
    const bool truth = value != 0.0;
    return (nots % 2 == 0) == truth ? 1.0 : 0.0;
  }

  double comparison() {
    const double lhs = sum();
    static constexpr std::string_view kOperators[] = {"==", "!=", "<=", ">=", "<", ">"};
    for (const auto op : kOperators) {
      if (!take(op)) continue;
      const double rhs = sum();
      bool holds = false;
      if (op == "==") holds = lhs == rhs;
      if (op == "!=") holds = lhs != rhs;
      if (op == "<=") holds = lhs <= rhs;
      if (op == ">=") holds = lhs >= rhs;
      if (op == "<") holds = lhs < rhs;
      if (op == ">") holds = lhs > rhs;
      return holds ? 1.0 : 0.0;
    }
    return lhs;
  }

  double sum() {
    double value = product();
    for (;;) {
      if (take("+")) {
        value += product();
      } else if (take("-")) {
        value -= product();
      } else {
        return value;
      }
    }
  }

  double product() {
    double value = unary();
    for (;;) {
      skip_space();
      const std::size_t at = pos_;
      if (take("*")) {
        value *= unary();
      } else if (take("/") || take("%")) {
        const bool modulo = text_[at] == '%';
        const double rhs = unary();
        if (rhs == 0.0) fail(at, modulo ? "modulo by zero" : "division by zero");
        value = modulo ? std::fmod(value, rhs) : value / rhs;
      } else {
        return value;
      }
    }
  }

  double unary() {
    int signs = 0;  // a run of minus signs, counted instead of recursed into
    while (take("-")) ++signs;
    const double value = primary();
    return signs % 2 == 0 ? value : -value;
  }

  double primary() {
    skip_space();
    if (pos_ >= text_.size()) fail(pos_, "expected a number, a parameter or '(' at the end");
    const char c = text_[pos_];
    if (c == '(') {
      // A hostile file's nesting must not exhaust the stack.
      if (++depth_ > kMaxDepth) fail(pos_, fmt::format("more than {} nested parentheses", kMaxDepth));
      ++pos_;
      const double value = or_expression();
      --depth_;
      if (!take(")")) fail(pos_, "expected ')'");
      return value;
    }
    if (c == '$') return parameter();
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(c))) return word();
    fail(pos_, fmt::format("unexpected '{}'", c));
  }

  double number() {
    const std::size_t start = pos_;
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text_.data() + pos_, text_.data() + text_.size(), value);
    if (ec != std::errc()) fail(start, "expected a number");
    pos_ = static_cast<std::size_t>(end - text_.data());
    return value;
  }

  std::string_view name() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() &&
           (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_' || text_[pos_] == '.'))
      ++pos_;
    return text_.substr(start, pos_ - start);
  }

  double parameter() {
    const std::size_t start = pos_++;
    const std::string_view parameter_name = name();
    if (parameter_name.empty()) fail(start, "expected a parameter name after '$'");
    const Parameter* parameter = scope_.find(parameter_name);
    if (parameter == nullptr) fail(start, fmt::format("unknown parameter '{}'", parameter_name));
    if (parameter->type == ParameterType::kBoolean) return parameter->value == "true" ? 1.0 : 0.0;
    double value = 0.0;
    const auto& text = parameter->value;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size())
      fail(start, fmt::format("parameter '{}' is '{}', not a number", parameter_name, text));
    return value;
  }

  double word() {
    const std::size_t start = pos_;
    const std::string word{name()};
    if (word == "true") return 1.0;
    if (word == "false") return 0.0;
    using Unary = double (*)(double);
    static const std::map<std::string, Unary, std::less<>> kUnary = {
        {"round", [](double x) { return std::round(x); }},
        {"floor", [](double x) { return std::floor(x); }},
        {"ceil", [](double x) { return std::ceil(x); }},
        {"sqrt", [](double x) { return std::sqrt(x); }},
        {"abs", [](double x) { return std::fabs(x); }},
        {"exp", [](double x) { return std::exp(x); }},
        {"log", [](double x) { return std::log(x); }},
        {"sin", [](double x) { return std::sin(x); }},
        {"cos", [](double x) { return std::cos(x); }},
        {"tan", [](double x) { return std::tan(x); }},
        {"asin", [](double x) { return std::asin(x); }},
        {"acos", [](double x) { return std::acos(x); }},
        {"atan", [](double x) { return std::atan(x); }},
        {"sign", [](double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }}};
    using Binary = double (*)(double, double);
    static const std::map<std::string, Binary, std::less<>> kBinary = {
        {"pow", [](double a, double b) { return std::pow(a, b); }},
        {"min", [](double a, double b) { return std::fmin(a, b); }},
        {"max", [](double a, double b) { return std::fmax(a, b); }}};
    const auto one = kUnary.find(word);
    const auto two = kBinary.find(word);
    if (one == kUnary.end() && two == kBinary.end())
      fail(start, fmt::format("unknown name '{}' (a parameter is written $name; functions: round, floor, ceil, "
                              "sqrt, pow, abs, sign, min, max, exp, log, sin, cos, tan, asin, acos, atan)",
                              word));
    if (!take("(")) fail(pos_, fmt::format("expected '(' after '{}'", word));
    const double a = or_expression();
    double value = 0.0;
    if (two != kBinary.end()) {
      if (!take(",")) fail(pos_, fmt::format("expected ',' ('{}' takes two arguments)", word));
      value = two->second(a, or_expression());
    } else {
      value = one->second(a);
    }
    if (!take(")")) fail(pos_, "expected ')'");
    if (!std::isfinite(value)) fail(start, fmt::format("'{}' is not defined there", word));
    return value;
  }

  static constexpr int kMaxDepth = 200;
  std::string_view text_;
  const ParameterScope& scope_;
  int depth_ = 0;
  SourceLocation where_;
  std::size_t pos_ = 0;
};

}  // namespace

double evaluate_expression(std::string_view text, const ParameterScope& scope, const SourceLocation& where) {
  return Evaluator(text, scope, where).run();
}

}  // namespace emrm::openscenario
