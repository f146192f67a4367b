#pragma once

// Predicates over named numeric factors ("ttc_s < 0.7 && mu < 0.3"), parsed by muparser.
// Operators: + - * / ^, comparisons < <= > >= == !=, && || and prefix !, parentheses,
// the usual functions (abs, min, max, sqrt, ...).

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/core/yaml.hpp"

namespace emrm::core {

/// A compiled expression over a fixed list of variables. Copyable (a copy recompiles).
/// Evaluation is not thread-safe on one object: give each thread its own copy.
class Expression {
 public:
  /// Compiles `text`. Throws InputError at `where` (moved to the offending column when known)
  /// if the text is not a valid expression or uses a name not in `variables`.
  Expression(std::string text, std::vector<std::string> variables, SourceLocation where);
  /// Compiles a YAML scalar, so errors point into the file.
  Expression(const YamlNode& node, std::vector<std::string> variables);
  ~Expression();
  Expression(const Expression& other);
  Expression& operator=(const Expression& other);
  Expression(Expression&&) noexcept;
  Expression& operator=(Expression&&) noexcept;

  /// Value for `values`, given in the order of `variables()`. Precondition: sizes match.
  [[nodiscard]] double evaluate(std::span<const double> values) const;
  /// True when the value is non-zero (a predicate that holds).
  [[nodiscard]] bool holds(std::span<const double> values) const { return evaluate(values) != 0.0; }

  [[nodiscard]] const std::string& text() const noexcept { return text_; }
  [[nodiscard]] const std::vector<std::string>& variables() const noexcept { return variables_; }
  /// The variables the expression actually reads, in declaration order.
  [[nodiscard]] std::vector<std::string> used_variables() const;
  [[nodiscard]] const SourceLocation& where() const noexcept { return where_; }

 private:
  struct Impl;
  void compile();

  std::string text_;
  std::vector<std::string> variables_;
  SourceLocation where_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace emrm::core
