#include "emrm/scenario/pict_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <optional>

#include "emrm/core/text.hpp"

namespace emrm::scenario {

namespace {

enum class Tri { kFalse, kTrue, kUnknown };

Tri tri_not(Tri a) { return a == Tri::kUnknown ? a : (a == Tri::kTrue ? Tri::kFalse : Tri::kTrue); }
Tri tri_and(Tri a, Tri b) {
  if (a == Tri::kFalse || b == Tri::kFalse) return Tri::kFalse;
  return a == Tri::kTrue && b == Tri::kTrue ? Tri::kTrue : Tri::kUnknown;
}
Tri tri_or(Tri a, Tri b) { return tri_not(tri_and(tri_not(a), tri_not(b))); }

std::optional<double> as_number(const std::string& s) {
  if (s.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

// A predicate tree. Relations are compiled to truth tables over value indices, so evaluation on a
// partial row is a lookup, with "unknown" when a parameter it reads is unassigned.
struct PictModel::Constraint {
  enum class Kind { kAnd, kOr, kNot, kIf, kUnary, kBinary };
  Kind kind = Kind::kUnary;
  std::vector<std::shared_ptr<const Constraint>> children;  // kIf: condition, then, [else]
  int p = 0;                                                // kUnary, kBinary
  int q = 0;                                                // kBinary
  std::vector<char> table;                                  // kUnary: [v of p]; kBinary: [v_p * levels(q) + v_q]
  int q_levels = 0;
  SourceLocation where;

  [[nodiscard]] Tri eval(std::span<const int> row) const {
    switch (kind) {
      case Kind::kAnd: {  // n-ary: a long chain of ANDs is one node, not a deep tree
        Tri all = Tri::kTrue;
        for (const auto& c : children)
          if ((all = tri_and(all, c->eval(row))) == Tri::kFalse) break;
        return all;
      }
      case Kind::kOr: {
        Tri any = Tri::kFalse;
        for (const auto& c : children)
          if ((any = tri_or(any, c->eval(row))) == Tri::kTrue) break;
        return any;
      }
      case Kind::kNot:
        return tri_not(children[0]->eval(row));
      case Kind::kIf: {
        const Tri c = children[0]->eval(row);
        const Tri then_part = tri_or(tri_not(c), children[1]->eval(row));
        const Tri else_part = children.size() > 2 ? tri_or(c, children[2]->eval(row)) : Tri::kTrue;
        return tri_and(then_part, else_part);
      }
      case Kind::kUnary: {
        const int v = row[static_cast<std::size_t>(p)];
        if (v == kDontCare) return Tri::kUnknown;
        return table[static_cast<std::size_t>(v)] ? Tri::kTrue : Tri::kFalse;
      }
      case Kind::kBinary: {
        const int vp = row[static_cast<std::size_t>(p)];
        const int vq = row[static_cast<std::size_t>(q)];
        if (vp == kDontCare || vq == kDontCare) return Tri::kUnknown;
        return table[static_cast<std::size_t>(vp) * static_cast<std::size_t>(q_levels) + static_cast<std::size_t>(vq)]
                   ? Tri::kTrue
                   : Tri::kFalse;
      }
    }
    return Tri::kUnknown;
  }
};

namespace {

using Node = PictModel::Constraint;
using NodePtr = std::shared_ptr<const Node>;

struct Token {
  enum class Kind { kParam, kString, kNumber, kWord, kOp, kPunct, kEnd };
  Kind kind = Kind::kEnd;
  std::string text;
  int line = 0;
  int column = 0;
};

class ConstraintParser {
 public:
  ConstraintParser(std::string_view text, int first_line, const std::string& file,
                   const std::vector<PictParameter>& params)
      : file_(file), params_(params) {
    tokenize(text, first_line);
  }

  std::vector<NodePtr> parse_all() {
    std::vector<NodePtr> out;
    while (peek().kind != Token::Kind::kEnd) {
      const Token start = peek();
      NodePtr c;
      if (is_word("IF")) {
        next();
        auto node = std::make_shared<Node>();
        node->kind = Node::Kind::kIf;
        node->children.push_back(predicate());
        expect_word("THEN");
        node->children.push_back(predicate());
        if (is_word("ELSE")) {
          next();
          node->children.push_back(predicate());
        }
        c = node;
      } else {
        c = predicate();
      }
      if (!(peek().kind == Token::Kind::kPunct && peek().text == ";"))
        fail(peek(), "expected ';' at the end of the constraint, found " + describe(peek()));
      next();
      auto located = std::make_shared<Node>(*c);
      located->where = {file_, start.line, start.column};
      out.push_back(located);
    }
    return out;
  }

 private:
  [[noreturn]] void fail(const Token& t, const std::string& message) const {
    throw InputError({file_, t.line, t.column}, message);
  }
  static std::string describe(const Token& t) {
    return t.kind == Token::Kind::kEnd ? "end of file" : "'" + t.text + "'";
  }

  void tokenize(std::string_view s, int line) {
    int col = 1;
    std::size_t i = 0;
    auto advance = [&](std::size_t n) {
      for (std::size_t k = 0; k < n; ++k, ++i) {
        if (s[i] == '\n') {
          ++line;
          col = 1;
        } else {
          ++col;
        }
      }
    };
    while (i < s.size()) {
      const char ch = s[i];
      if (std::isspace(static_cast<unsigned char>(ch))) {
        advance(1);
        continue;
      }
      if (ch == '#') {  // a comment runs to the end of the line
        while (i < s.size() && s[i] != '\n') advance(1);
        continue;
      }
      Token t;
      t.line = line;
      t.column = col;
      if (ch == '[') {
        const auto end = s.find(']', i);
        if (end == std::string_view::npos) fail(t, "expected ']' closing the parameter name");
        t.kind = Token::Kind::kParam;
        t.text = trim(s.substr(i + 1, end - i - 1));
        advance(end - i + 1);
      } else if (ch == '"') {
        const auto end = s.find('"', i + 1);
        if (end == std::string_view::npos) fail(t, "expected '\"' closing the string");
        t.kind = Token::Kind::kString;
        t.text = std::string(s.substr(i + 1, end - i - 1));
        advance(end - i + 1);
      } else if (std::isdigit(static_cast<unsigned char>(ch)) || ch == '-' || ch == '+' || ch == '.') {
        std::size_t j = i + 1;
        while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '.' ||
                                ((s[j] == '-' || s[j] == '+') && (s[j - 1] == 'e' || s[j - 1] == 'E'))))
          ++j;
        t.kind = Token::Kind::kNumber;
        t.text = std::string(s.substr(i, j - i));
        if (!as_number(t.text)) fail(t, "expected a number, found '" + t.text + "'");
        advance(j - i);
      } else if (std::isalpha(static_cast<unsigned char>(ch))) {
        std::size_t j = i;
        while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '_')) ++j;
        t.kind = Token::Kind::kWord;
        t.text = upper(std::string(s.substr(i, j - i)));
        advance(j - i);
      } else if (ch == '<' || ch == '>' || ch == '=') {
        std::size_t n = 1;
        if (i + 1 < s.size() && (s[i + 1] == '=' || (ch == '<' && s[i + 1] == '>'))) n = 2;
        t.kind = Token::Kind::kOp;
        t.text = std::string(s.substr(i, n));
        advance(n);
      } else if (ch == '(' || ch == ')' || ch == '{' || ch == '}' || ch == ',' || ch == ';') {
        t.kind = Token::Kind::kPunct;
        t.text = std::string(1, ch);
        advance(1);
      } else {
        fail(t, std::string("unexpected character '") + ch + "' in a constraint");
      }
      tokens_.push_back(t);
    }
    Token end;
    end.line = line;
    end.column = col;
    tokens_.push_back(end);
  }

  const Token& peek() const { return tokens_[pos_]; }
  Token next() { return tokens_[pos_ < tokens_.size() - 1 ? pos_++ : pos_]; }
  bool is_word(const char* w) const { return peek().kind == Token::Kind::kWord && peek().text == w; }
  void expect_word(const char* w) {
    if (!is_word(w)) fail(peek(), std::string("expected ") + w + ", found " + describe(peek()));
    next();
  }
  bool is_punct(const char* p) const { return peek().kind == Token::Kind::kPunct && peek().text == p; }

  // `operand (WORD operand)*` as one n-ary node of `kind` (the operand alone when there is one).
  template <class Operand>
  NodePtr chain(Node::Kind kind, const char* word, Operand operand) {
    NodePtr first = operand();
    if (!is_word(word)) return first;
    auto n = std::make_shared<Node>();
    n->kind = kind;
    n->children.push_back(std::move(first));
    while (is_word(word)) {
      next();
      n->children.push_back(operand());
    }
    return n;
  }

  NodePtr predicate() {
    return chain(Node::Kind::kOr, "OR", [this] { return conjunction(); });
  }
  NodePtr conjunction() {
    return chain(Node::Kind::kAnd, "AND", [this] { return unary(); });
  }
  NodePtr unary() {
    // Parentheses and NOTs recurse: a depth limit keeps a hostile file from overflowing the stack.
    struct Depth {
      int& d;
      explicit Depth(int& depth) : d(++depth) {}
      ~Depth() { --d; }
    } depth(depth_);
    if (depth_ > kMaxNesting)
      fail(peek(),
           fmt::format("parentheses and NOTs nested more than {} deep; expected a flatter constraint", kMaxNesting));
    if (is_word("NOT")) {
      next();
      auto n = std::make_shared<Node>();
      n->kind = Node::Kind::kNot;
      n->children = {unary()};
      return n;
    }
    if (is_punct("(")) {
      next();
      NodePtr inner = predicate();
      if (!is_punct(")")) fail(peek(), "expected ')', found " + describe(peek()));
      next();
      return inner;
    }
    return relation();
  }

  int parameter(const Token& t) const {
    for (std::size_t i = 0; i < params_.size(); ++i)
      if (params_[i].name == t.text) return static_cast<int>(i);
    fail(t, "unknown parameter [" + t.text + "]");
  }

  // Is value `v` related by `op` to literal `lit`? Ordering needs numbers on both sides.
  bool relate(const std::string& v, const std::string& op, const Token& lit, const Token& op_token,
              const std::string& param) const {
    const auto a = as_number(v);
    const auto b = as_number(lit.text);
    const bool numeric = a && b && lit.kind == Token::Kind::kNumber;
    if (op == "=") return numeric ? *a == *b : v == lit.text;
    if (op == "<>") return numeric ? *a != *b : v != lit.text;
    if (!b) fail(lit, "ordering comparison '" + op + "' needs a number, found '" + lit.text + "'");
    if (!a)
      fail(op_token, "ordering comparison '" + op + "' needs numeric values, but [" + param + "] has '" + v + "'");
    if (op == "<") return *a < *b;
    if (op == "<=") return *a <= *b;
    if (op == ">") return *a > *b;
    return *a >= *b;
  }

  NodePtr relation() {
    const Token p = next();
    if (p.kind != Token::Kind::kParam) fail(p, "expected a parameter like [Name], found " + describe(p));
    const int pi = parameter(p);
    const auto& pvalues = params_[static_cast<std::size_t>(pi)].values;
    auto n = std::make_shared<Node>();
    n->p = pi;
    bool negate = false;
    if (is_word("NOT")) {  // [P] NOT IN {...}
      next();
      negate = true;
      if (!is_word("IN")) fail(peek(), "expected IN after NOT, found " + describe(peek()));
    }
    if (is_word("IN")) {
      next();
      if (!is_punct("{")) fail(peek(), "expected '{' after IN, found " + describe(peek()));
      next();
      n->kind = Node::Kind::kUnary;
      n->table.assign(pvalues.size(), negate ? 1 : 0);
      while (true) {
        const Token lit = next();
        if (lit.kind != Token::Kind::kString && lit.kind != Token::Kind::kNumber)
          fail(lit, "expected a value in the IN set, found " + describe(lit));
        for (std::size_t v = 0; v < pvalues.size(); ++v)
          if (relate(pvalues[v], "=", lit, lit, p.text)) n->table[v] = negate ? 0 : 1;
        if (is_punct(",")) {
          next();
          continue;
        }
        if (!is_punct("}")) fail(peek(), "expected ',' or '}' in the IN set, found " + describe(peek()));
        next();
        break;
      }
      return n;
    }
    const Token op = next();
    if (op.kind == Token::Kind::kWord && op.text == "LIKE") fail(op, "LIKE is not supported by emrm");
    if (op.kind != Token::Kind::kOp) fail(op, "expected =, <>, <, <=, >, >= or IN, found " + describe(op));
    const Token rhs = next();
    if (rhs.kind == Token::Kind::kParam) {
      const int qi = parameter(rhs);
      const auto& qvalues = params_[static_cast<std::size_t>(qi)].values;
      n->kind = Node::Kind::kBinary;
      n->q = qi;
      n->q_levels = static_cast<int>(qvalues.size());
      for (const auto& pv : pvalues)
        for (const auto& qv : qvalues) {
          Token as_literal = rhs;
          as_literal.text = qv;
          as_literal.kind = as_number(qv) ? Token::Kind::kNumber : Token::Kind::kString;
          n->table.push_back(relate(pv, op.text, as_literal, op, p.text) ? 1 : 0);
        }
      return n;
    }
    if (rhs.kind != Token::Kind::kString && rhs.kind != Token::Kind::kNumber)
      fail(rhs, "expected a value or a parameter after '" + op.text + "', found " + describe(rhs));
    n->kind = Node::Kind::kUnary;
    for (const auto& pv : pvalues) n->table.push_back(relate(pv, op.text, rhs, op, p.text) ? 1 : 0);
    return n;
  }

  static constexpr int kMaxNesting = 200;

  const std::string& file_;
  const std::vector<PictParameter>& params_;
  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  int depth_ = 0;  // of unary() calls in progress
};

bool starts_constraint(const std::string& line) {
  const std::string u = upper(line);
  return !u.empty() &&
         (u[0] == '[' || u[0] == '(' || u.rfind("IF ", 0) == 0 || u.rfind("IF[", 0) == 0 || u.rfind("NOT ", 0) == 0);
}

// Throws InputError when no row satisfies `model`'s constraints, at the first constraint that with
// those before it excludes every row. One search budget covers the whole check, culprit included;
// running out is reported at the first constraint, since no single one is to blame yet.
void check_satisfiable(const PictModel& model, const std::vector<NodePtr>& constraints,
                       std::uint64_t max_search_steps) {
  const auto& params = model.parameters();
  const std::vector<int> empty(params.size(), kDontCare);
  const SourceLocation& first = constraints.front()->where;
  SearchBudget budget(max_search_steps);
  try {
    if (complete_row(model.levels(), empty, model.row_violates(), budget)) return;
  } catch (const UsageError& e) {
    throw InputError(first, e.what());
  }
  const std::string unsatisfiable = "the constraints are unsatisfiable: no row satisfies them all";
  try {
    for (std::size_t k = 1; k <= constraints.size(); ++k) {
      const PictModel prefix(
          params, std::vector<NodePtr>(constraints.begin(), constraints.begin() + static_cast<std::ptrdiff_t>(k)));
      if (!complete_row(prefix.levels(), empty, prefix.row_violates(), budget))
        throw InputError(constraints[k - 1]->where, unsatisfiable);
    }
  } catch (const UsageError&) {
    // Known to be unsatisfiable; only the culprit is missing.
    throw InputError(first, fmt::format("{} (finding the first constraint to blame took more than {} search steps; "
                                        "ca --max-search-steps raises it)",
                                        unsatisfiable, max_search_steps));
  }
}

}  // namespace

PictModel::PictModel(std::vector<PictParameter> parameters, std::vector<std::shared_ptr<const Constraint>> constraints)
    : parameters_(std::move(parameters)), constraints_(std::move(constraints)) {}

std::vector<int> PictModel::levels() const {
  std::vector<int> l;
  for (const auto& p : parameters_) l.push_back(static_cast<int>(p.values.size()));
  return l;
}

bool PictModel::violates(std::span<const int> row) const {
  return std::any_of(constraints_.begin(), constraints_.end(),
                     [&](const auto& c) { return c->eval(row) == Tri::kFalse; });
}

RowViolates PictModel::row_violates() const {
  if (constraints_.empty()) return {};
  return [this](std::span<const int> row) { return violates(row); };
}

PictModel parse_pict_model(std::string_view text, const std::string& file, std::uint64_t max_search_steps) {
  std::vector<PictParameter> params;
  std::size_t pos = 0;
  int line_no = 0;
  std::size_t constraints_at = text.size();
  int constraints_line = 0;
  while (pos < text.size()) {
    const auto eol = std::min(text.find('\n', pos), text.size());
    const std::string_view raw = text.substr(pos, eol - pos);
    ++line_no;
    const std::string line = trim(raw);
    const int indent = static_cast<int>(raw.find_first_not_of(" \t")) + 1;
    if (line.empty() || line[0] == '#') {
      pos = eol + 1;
      continue;
    }
    if (starts_constraint(line)) {
      constraints_at = pos;
      constraints_line = line_no;
      break;
    }
    if (line[0] == '{')
      throw InputError({file, line_no, indent}, "sub-models ({ A, B } @ N) are not supported by emrm");
    const auto colon = raw.find(':');
    if (colon == std::string_view::npos)
      throw InputError({file, line_no, indent}, "expected a parameter line 'Name: value1, value2, ...'");
    PictParameter p;
    p.name = trim(raw.substr(0, colon));
    p.where = {file, line_no, indent};
    if (p.name.empty()) throw InputError(p.where, "the parameter has no name before ':'");
    for (const auto& other : params)
      if (other.name == p.name)
        throw InputError(p.where, "duplicate parameter '" + p.name + "' (first defined at line " +
                                      std::to_string(other.where.line) + ")");
    std::size_t start = colon + 1;
    while (true) {
      const auto comma = std::min(raw.find(',', start), raw.size());
      const std::string value = trim(raw.substr(start, comma - start));
      const auto offset = raw.substr(start, comma - start).find_first_not_of(" \t");
      const int col = static_cast<int>(start + (offset == std::string_view::npos ? 0 : offset)) + 1;
      if (value.empty()) {
        if (comma == raw.size() && p.values.empty())
          throw InputError({file, line_no, col}, "parameter '" + p.name + "' has no values");
        throw InputError({file, line_no, col}, "empty value in parameter '" + p.name + "'");
      }
      if (std::find(p.values.begin(), p.values.end(), value) != p.values.end())
        throw InputError({file, line_no, col}, "duplicate value '" + value + "' in parameter '" + p.name + "'");
      p.values.push_back(value);
      if (comma == raw.size()) break;
      start = comma + 1;
    }
    params.push_back(std::move(p));
    pos = eol + 1;
  }
  if (params.empty()) throw InputError({file, std::max(line_no, 1), 1}, "the model declares no parameters");
  std::vector<NodePtr> constraints;
  if (constraints_at < text.size())
    constraints = ConstraintParser(text.substr(constraints_at), constraints_line, file, params).parse_all();
  PictModel model(params, constraints);
  if (!constraints.empty()) check_satisfiable(model, constraints, max_search_steps);
  return model;
}

PictModel load_pict_model(const std::filesystem::path& path, std::uint64_t max_search_steps) {
  return parse_pict_model(core::read_input_file(path), path.string(), max_search_steps);
}

}  // namespace emrm::scenario
