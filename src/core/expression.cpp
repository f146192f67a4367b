#include "emrm/core/expression.hpp"

#include <fmt/format.h>
#include <muParser.h>

#include <cassert>

namespace emrm::core {

struct Expression::Impl {
  mu::Parser parser;
  std::vector<double> values;  // muparser reads variables through pointers into this
};

namespace {

double logical_not(double x) { return x == 0.0 ? 1.0 : 0.0; }

// A YAML scalar's text starts one column after its mark when it is quoted.
int text_column(const YamlNode& node) {
  const int column = node.location().column;
  return node.raw().Tag() == "!" ? column + 1 : column;
}

}  // namespace

Expression::Expression(std::string text, std::vector<std::string> variables, SourceLocation where)
    : text_(std::move(text)), variables_(std::move(variables)), where_(std::move(where)) {
  compile();
}

Expression::Expression(const YamlNode& node, std::vector<std::string> variables)
    : text_(node.as_string()), variables_(std::move(variables)), where_(node.location()) {
  where_.column = text_column(node);
  compile();
}

Expression::~Expression() = default;
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;

Expression::Expression(const Expression& other)
    : text_(other.text_), variables_(other.variables_), where_(other.where_) {
  compile();
}

Expression& Expression::operator=(const Expression& other) {
  if (this != &other) *this = Expression(other);
  return *this;
}

void Expression::compile() {
  impl_ = std::make_unique<Impl>();
  impl_->values.assign(variables_.size(), 0.0);
  if (text_.find_first_not_of(" \t") == std::string::npos)
    throw InputError(where_, "expected an expression, got empty text");
  try {
    impl_->parser.DefineInfixOprt("!", logical_not);
    for (std::size_t i = 0; i < variables_.size(); ++i) impl_->parser.DefineVar(variables_[i], &impl_->values[i]);
    impl_->parser.SetExpr(text_);
    impl_->parser.Eval();  // forces the parse, so every error surfaces here
  } catch (const mu::Parser::exception_type& e) {
    SourceLocation at = where_;
    const int pos = e.GetPos() >= 0 ? static_cast<int>(e.GetPos()) : -1;
    if (at.column > 0 && pos >= 0) at.column += pos;
    std::string message;
    if (e.GetCode() == mu::ecUNASSIGNABLE_TOKEN && !e.GetToken().empty()) {
      std::string known;
      for (const auto& v : variables_) known += (known.empty() ? "" : ", ") + v;
      message = fmt::format("unknown name '{}' in expression '{}'; expected one of: {}", e.GetToken(), text_,
                            known.empty() ? "(no factors declared)" : known);
    } else {
      message = fmt::format("invalid expression '{}': {}", text_, e.GetMsg());
    }
    throw InputError(at, message);
  }
}

double Expression::evaluate(std::span<const double> values) const {
  assert(values.size() == impl_->values.size());
  std::copy(values.begin(), values.end(), impl_->values.begin());
  return impl_->parser.Eval();
}

std::vector<std::string> Expression::used_variables() const {
  const auto& used = impl_->parser.GetUsedVar();
  std::vector<std::string> out;
  for (const auto& v : variables_)
    if (used.count(v) != 0) out.push_back(v);
  return out;
}

}  // namespace emrm::core
