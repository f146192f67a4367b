#include "emrm/fsm/load.hpp"

#include <fmt/format.h>

#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "emrm/core/text.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/fsm/operations.hpp"

namespace emrm::fsm {
namespace {

using core::Ref;  // a name that refers to a state or an event, with where it was written

/// A state or an event: `{id: X, description: ...}` or just `X`.
struct Declaration {
  std::string id;
  std::string description;
  SourceLocation where;

  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("id", id);
    a.optional("description", description);
  }
};

struct FsmFile {
  std::string name;
  std::string description;
  std::vector<Declaration> states;
  std::vector<Declaration> events;
  Ref initial;
  std::vector<Ref> marked;
  std::vector<core::TransitionRef> transitions;

  template <class A>
  void serialize(A& a) {
    a.required("name", name);
    a.optional("description", description);
    a.required("states", states);
    a.required("events", events);
    a.required("initial", initial);
    a.required("marked", marked);
    a.required("transitions", transitions);
  }
};

}  // namespace
}  // namespace emrm::fsm

namespace emrm::core {

template <>
struct YamlCodec<fsm::Declaration> {
  static void read(const YamlNode& n, fsm::Declaration& v) {
    if (n.is_scalar()) {
      v.where = n.location();
      v.id = n.as_string();
      return;
    }
    if (!n.is_map()) n.fail("expected an id or a mapping with 'id' and 'description', got " + n.describe());
    read_yaml(n, v);
  }
};

}  // namespace emrm::core

namespace emrm::fsm {
namespace {

constexpr std::size_t kMaxNamesInMessage = 12;

/// "a, b, c" (or the first few and a count), for "expected one of" messages.
std::string name_list(const std::vector<std::string>& names) {
  if (names.size() <= kMaxNamesInMessage) return core::join(names, ", ");
  std::vector<std::string> head(names.begin(), names.begin() + kMaxNamesInMessage);
  return fmt::format("{} and {} more", core::join(head, ", "), names.size() - kMaxNamesInMessage);
}

bool is_id_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
}

void check_id(const Declaration& d, std::string_view kind) {
  if (d.id.empty()) throw InputError(d.where, fmt::format("expected a non-empty {} id", kind));
  for (char c : d.id)
    if (!is_id_char(c))
      throw InputError(d.where, fmt::format("invalid {} id '{}': expected letters, digits, '_', '-' or '.' only "
                                            "(words are written as ids separated by spaces)",
                                            kind, d.id));
}

/// Declared ids of one kind, for lookups and messages.
class Names {
 public:
  explicit Names(std::string_view kind) : kind_(kind) {}

  void declare(const Declaration& d) {
    check_id(d, kind_);
    auto [it, inserted] = where_.emplace(d.id, d.where);
    if (!inserted)
      throw InputError(d.where,
                       fmt::format("duplicate {} id '{}' (first declared at {})", kind_, d.id, it->second.str()));
    order_.push_back(d.id);
  }

  /// Throws InputError at the reference unless it names a declared id. `role` says what it is for.
  void require(const Ref& ref, std::string_view role) const {
    if (where_.contains(ref.id)) return;
    if (order_.empty())
      throw InputError(ref.where,
                       fmt::format("{} '{}' is not a declared {}: no {}s are declared", role, ref.id, kind_, kind_));
    throw InputError(ref.where, fmt::format("{} '{}' is not a declared {}; expected one of: {}", role, ref.id, kind_,
                                            name_list(order_)));
  }

 private:
  std::string kind_;
  std::map<std::string, SourceLocation> where_;
  std::vector<std::string> order_;
};

Generator build(const FsmFile& file) {
  Names states("state");
  Names events("event");
  for (const auto& s : file.states) states.declare(s);
  for (const auto& e : file.events) events.declare(e);

  states.require(file.initial, "initial state");
  std::map<std::string, SourceLocation> marked;
  for (const auto& m : file.marked) {
    states.require(m, "marked state");
    auto [it, inserted] = marked.emplace(m.id, m.where);
    if (!inserted)
      throw InputError(m.where, fmt::format("state '{}' is marked twice (first at {})", m.id, it->second.str()));
  }
  std::map<std::tuple<std::string, std::string, std::string>, SourceLocation> seen;
  for (const auto& t : file.transitions) {
    states.require(t.from, "transition source");
    events.require(t.event, "transition event");
    states.require(t.to, "transition target");
    auto [it, inserted] = seen.emplace(std::tuple{t.from.id, t.event.id, t.to.id}, t.where);
    if (!inserted)
      throw InputError(t.where, fmt::format("duplicate transition {} --{}--> {} (first at {})", t.from.id, t.event.id,
                                            t.to.id, it->second.str()));
  }

  // Everything is validated, so the Generator's own checks cannot fire from here on.
  Generator g(file.name, file.description);
  for (const auto& e : file.events) g.add_event(e.id, e.description, e.where);  // events first: δ's columns
  for (const auto& s : file.states) g.add_state(s.id, s.description, s.where);
  for (const auto& t : file.transitions) g.add_transition(t.from.id, t.event.id, t.to.id, t.where);
  g.set_initial(file.initial.id);
  for (const auto& m : file.marked) g.mark(m.id);
  return g;
}

Generator read_generator(const core::YamlNode& root) {
  FsmFile file;
  core::read_yaml(root, file);
  return build(file);
}

}  // namespace

Generator load_generator(const std::filesystem::path& path) { return read_generator(core::YamlNode::load_file(path)); }

Generator parse_generator(const std::string& text, const std::string& file_name) {
  return read_generator(core::YamlNode::parse(text, file_name));
}

std::vector<Trace> parse_traces(const std::string& text, const std::string& file_name) {
  std::vector<Trace> traces;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    auto events = split_word(line);
    if (events.empty()) continue;
    traces.push_back({std::move(events), {file_name, number, 1}});
  }
  return traces;
}

std::vector<Trace> load_traces(const std::filesystem::path& path) {
  return parse_traces(core::read_input_file(path), path.string());
}

}  // namespace emrm::fsm
