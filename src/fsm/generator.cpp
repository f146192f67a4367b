#include "emrm/fsm/generator.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace emrm::fsm {

Generator::Generator(std::string name, std::string description)
    : name_(std::move(name)), description_(std::move(description)) {}

void Generator::add_state(std::string id, std::string description, SourceLocation where) {
  if (id.empty()) throw Error("fsm: a state id must not be empty");
  if (state_index_.contains(id)) throw Error(fmt::format("fsm: duplicate state '{}'", id));
  state_index_.emplace(id, state_count());
  states_.push_back({std::move(id), std::move(description), std::move(where)});
  // Rows of δ are per state, so a new state only appends a row.
  delta_.resize(delta_.size() + events_.size(), kNone);
  outgoing_.emplace_back();
  marked_.push_back(0);
}

void Generator::add_event(std::string id, std::string description, SourceLocation where) {
  if (id.empty()) throw Error("fsm: an event id must not be empty");
  if (event_index_.contains(id)) throw Error(fmt::format("fsm: duplicate event '{}'", id));
  const std::size_t old_events = events_.size();
  event_index_.emplace(id, event_count());
  events_.push_back({std::move(id), std::move(description), std::move(where)});
  // A new column: lay the table out again (events are normally all added before transitions).
  std::vector<int> table(states_.size() * events_.size(), kNone);
  for (std::size_t s = 0; s < states_.size(); ++s)
    for (std::size_t e = 0; e < old_events; ++e) table[s * events_.size() + e] = delta_[s * old_events + e];
  delta_ = std::move(table);
}

void Generator::add_transition(const std::string& from, const std::string& event, const std::string& to,
                               SourceLocation where) {
  const int f = state_index(from);
  const int e = event_index(event);
  const int t = state_index(to);
  if (f == kNone) throw Error(fmt::format("fsm: transition from unknown state '{}'", from));
  if (e == kNone) throw Error(fmt::format("fsm: transition on unknown event '{}'", event));
  if (t == kNone) throw Error(fmt::format("fsm: transition to unknown state '{}'", to));
  if (has_transition(from, event, to))
    throw Error(fmt::format("fsm: duplicate transition {} --{}--> {}", from, event, to));
  const int index = static_cast<int>(transitions_.size());
  transitions_.push_back({from, event, to, std::move(where)});
  edges_.push_back({f, e, t});
  outgoing_[static_cast<std::size_t>(f)].push_back(index);
  int& first = delta_[slot(f, e)];
  if (first == kNone)
    first = index;
  else
    ++nondeterministic_pairs_;
}

void Generator::set_initial(const std::string& state) {
  const int s = state_index(state);
  if (s == kNone) throw Error(fmt::format("fsm: unknown initial state '{}'", state));
  initial_ = s;
}

void Generator::mark(const std::string& state) {
  const int s = state_index(state);
  if (s == kNone) throw Error(fmt::format("fsm: cannot mark unknown state '{}'", state));
  marked_[static_cast<std::size_t>(s)] = 1;
}

std::optional<std::string> Generator::initial() const {
  if (initial_ == kNone) return std::nullopt;
  return states_[static_cast<std::size_t>(initial_)].id;
}

std::vector<std::string> Generator::marked_states() const {
  std::vector<std::string> out;
  for (std::size_t s = 0; s < states_.size(); ++s)
    if (marked_[s] != 0) out.push_back(states_[s].id);
  return out;
}

bool Generator::has_transition(const std::string& from, const std::string& event, const std::string& to) const {
  const int f = state_index(from);
  const int e = event_index(event);
  const int t = state_index(to);
  if (f == kNone || e == kNone || t == kNone) return false;
  const auto& out = outgoing(f);
  return std::any_of(out.begin(), out.end(), [&](int i) {
    const auto& edge = edges_[static_cast<std::size_t>(i)];
    return edge.event == e && edge.to == t;
  });
}

bool Generator::is_marked(const std::string& state) const {
  const int s = state_index(state);
  return s != kNone && is_marked(s);
}

int Generator::state_index(const std::string& id) const {
  const auto it = state_index_.find(id);
  return it == state_index_.end() ? kNone : it->second;
}

int Generator::event_index(const std::string& id) const {
  const auto it = event_index_.find(id);
  return it == event_index_.end() ? kNone : it->second;
}

std::optional<std::string> Generator::step(const std::string& state, const std::string& event) const {
  const int s = state_index(state);
  const int e = event_index(event);
  if (s == kNone || e == kNone) return std::nullopt;
  const int next = step_index(s, e);
  if (next == kNone) return std::nullopt;
  return states_[static_cast<std::size_t>(next)].id;
}

std::optional<std::string> Generator::run(const std::string& state, const std::vector<std::string>& word) const {
  int s = state_index(state);
  if (s == kNone) return std::nullopt;
  for (const auto& event : word) {
    const int e = event_index(event);
    if (e == kNone) return std::nullopt;
    s = step_index(s, e);
    if (s == kNone) return std::nullopt;
  }
  return states_[static_cast<std::size_t>(s)].id;
}

std::vector<int> Generator::reach(const std::vector<std::string>& word) const {
  if (initial_ == kNone) return {};
  std::vector<int> current{initial_};
  std::vector<int> next;
  for (const auto& event : word) {
    const int e = event_index(event);
    if (e == kNone) return {};
    next.clear();
    for (int s : current) {
      if (is_deterministic()) {
        if (const int t = step_index(s, e); t != kNone) next.push_back(t);
        continue;
      }
      for (int i : outgoing(s))
        if (edges_[static_cast<std::size_t>(i)].event == e) next.push_back(edges_[static_cast<std::size_t>(i)].to);
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    if (next.empty()) return {};
    std::swap(current, next);
  }
  return current;
}

bool Generator::generates(const std::vector<std::string>& word) const { return !reach(word).empty(); }

bool Generator::marks(const std::vector<std::string>& word) const {
  const auto reached = reach(word);
  return std::any_of(reached.begin(), reached.end(), [&](int s) { return is_marked(s); });
}

}  // namespace emrm::fsm
