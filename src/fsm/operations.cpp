#include "emrm/fsm/operations.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <map>
#include <set>
#include <utility>

namespace emrm::fsm {
namespace {

using StateSet = std::vector<int>;  // sorted, unique state indices

std::size_t at(int index) { return static_cast<std::size_t>(index); }

std::vector<std::string> state_names(const Generator& g, const StateSet& states) {
  std::vector<std::string> out;
  out.reserve(states.size());
  for (int s : states) out.push_back(g.states()[at(s)].id);
  return out;
}

std::vector<std::string> names_where(const Generator& g, const std::vector<char>& mask, bool value) {
  std::vector<std::string> out;
  for (std::size_t s = 0; s < mask.size(); ++s)
    if ((mask[s] != 0) == value) out.push_back(g.states()[s].id);
  return out;
}

/// The states any path from `states` reaches on `event` (the subset construction's step).
StateSet successors(const Generator& g, const StateSet& states, int event) {
  StateSet next;
  for (int s : states) {
    if (g.is_deterministic()) {
      if (const int t = g.step_index(s, event); t != Generator::kNone) next.push_back(t);
      continue;
    }
    for (int i : g.outgoing(s)) {
      const auto& edge = g.indexed_transitions()[at(i)];
      if (edge.event == event) next.push_back(edge.to);
    }
  }
  std::sort(next.begin(), next.end());
  next.erase(std::unique(next.begin(), next.end()), next.end());
  return next;
}

bool any_marked(const Generator& g, const StateSet& states) {
  return std::any_of(states.begin(), states.end(), [&](int s) { return g.is_marked(s); });
}

std::vector<char> accessible_mask(const Generator& g) {
  std::vector<char> seen(at(g.state_count()), 0);
  if (g.initial_index() == Generator::kNone) return seen;
  std::vector<int> stack{g.initial_index()};
  seen[at(g.initial_index())] = 1;
  while (!stack.empty()) {
    const int s = stack.back();
    stack.pop_back();
    for (int i : g.outgoing(s)) {
      const int t = g.indexed_transitions()[at(i)].to;
      if (seen[at(t)] == 0) {
        seen[at(t)] = 1;
        stack.push_back(t);
      }
    }
  }
  return seen;
}

std::vector<char> coaccessible_mask(const Generator& g) {
  std::vector<std::vector<int>> incoming(at(g.state_count()));
  for (const auto& edge : g.indexed_transitions()) incoming[at(edge.to)].push_back(edge.from);
  std::vector<char> seen(at(g.state_count()), 0);
  std::vector<int> stack;
  for (int s = 0; s < g.state_count(); ++s)
    if (g.is_marked(s)) {
      seen[at(s)] = 1;
      stack.push_back(s);
    }
  while (!stack.empty()) {
    const int s = stack.back();
    stack.pop_back();
    for (int p : incoming[at(s)])
      if (seen[at(p)] == 0) {
        seen[at(p)] = 1;
        stack.push_back(p);
      }
  }
  return seen;
}

/// G with only the states in `keep`; everything else (events, order, names) as in G.
Generator restrict_to(const Generator& g, const std::vector<char>& keep) {
  Generator out(g.name(), g.description());
  for (const auto& e : g.events()) out.add_event(e.id, e.description, e.where);
  for (std::size_t s = 0; s < g.states().size(); ++s)
    if (keep[s] != 0) out.add_state(g.states()[s].id, g.states()[s].description, g.states()[s].where);
  for (std::size_t i = 0; i < g.transitions().size(); ++i) {
    const auto& edge = g.indexed_transitions()[i];
    if (keep[at(edge.from)] != 0 && keep[at(edge.to)] != 0) {
      const auto& t = g.transitions()[i];
      out.add_transition(t.from, t.event, t.to, t.where);
    }
  }
  if (const int s0 = g.initial_index(); s0 != Generator::kNone && keep[at(s0)] != 0)
    out.set_initial(g.states()[at(s0)].id);
  for (int s = 0; s < g.state_count(); ++s)
    if (keep[at(s)] != 0 && g.is_marked(s)) out.mark(g.states()[at(s)].id);
  return out;
}

std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b, bool& saturated) {
  if (a > std::numeric_limits<std::uint64_t>::max() - b) {
    saturated = true;
    return std::numeric_limits<std::uint64_t>::max();
  }
  return a + b;
}

/// The first path, in transition declaration order, that reads `events` (all known) from s0;
/// empty if there is none. Failed (position, state) pairs are remembered, so it is linear in
/// |trace|·|S| even on a non-deterministic machine.
std::vector<int> witness_path(const Generator& g, const std::vector<int>& events) {
  std::vector<int> path;
  if (g.initial_index() == Generator::kNone) return path;
  if (g.is_deterministic()) {
    int s = g.initial_index();
    for (int e : events) {
      const int t = g.transition_index(s, e);
      if (t == Generator::kNone) return {};
      path.push_back(t);
      s = g.indexed_transitions()[at(t)].to;
    }
    return path;
  }
  std::set<std::pair<std::size_t, int>> dead;
  struct Frame {
    int state;
    std::size_t next_choice;  // index into g.outgoing(state)
  };
  std::vector<Frame> stack{{g.initial_index(), 0}};
  while (!stack.empty()) {
    const std::size_t position = stack.size() - 1;  // events read so far
    if (position == events.size()) return path;
    Frame& top = stack.back();
    const auto& out = g.outgoing(top.state);
    bool advanced = false;
    while (top.next_choice < out.size()) {
      const int i = out[top.next_choice++];
      const auto& edge = g.indexed_transitions()[at(i)];
      if (edge.event != events[position] || dead.contains({position + 1, edge.to})) continue;
      path.push_back(i);
      stack.push_back({edge.to, 0});
      advanced = true;
      break;
    }
    if (advanced) continue;
    dead.insert({position, top.state});
    stack.pop_back();
    if (!path.empty()) path.pop_back();
  }
  return {};
}

}  // namespace

std::vector<std::string> split_word(std::string_view text) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i])) != 0) ++i;
    const std::size_t start = i;
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i])) == 0) ++i;
    if (i > start) out.emplace_back(text.substr(start, i - start));
  }
  return out;
}

std::vector<std::string> trace_word(const Generator& g, const std::vector<std::string>& word) {
  std::vector<std::string> trace;
  auto state = g.initial();
  if (!state) return trace;
  trace.push_back(*state);
  for (const auto& e : word) {
    auto next = g.step(*state, e);
    if (!next) break;
    trace.push_back(e);
    trace.push_back(*next);
    state = next;
  }
  return trace;
}

WordEvaluation evaluate_word(const Generator& g, const std::vector<std::string>& word) {
  WordEvaluation result;
  if (g.initial_index() == Generator::kNone) return result;
  StateSet current{g.initial_index()};
  for (std::size_t k = 0; k < word.size(); ++k) {
    const int e = g.event_index(word[k]);
    StateSet next;
    if (e != Generator::kNone) next = successors(g, current, e);
    if (next.empty()) {
      result.failed_at = k + 1;
      result.failed_event = word[k];
      result.unknown_event = e == Generator::kNone;
      result.failed_from = state_names(g, current);
      return result;
    }
    current = std::move(next);
  }
  result.generated = true;
  result.marked = any_marked(g, current);
  result.reached = state_names(g, current);
  return result;
}

WordEnumeration enumerate_words(const Generator& g, int max_length, std::size_t limit) {
  if (max_length < 0) throw Error(fmt::format("fsm: word length must be >= 0, got {}", max_length));
  WordEnumeration result;
  result.max_length = max_length;
  const auto n = static_cast<std::size_t>(max_length);
  result.words_per_length.assign(n + 1, 0);
  result.marked_per_length.assign(n + 1, 0);
  if (g.initial_index() == Generator::kNone) return result;

  // Subset construction, built only as deep as needed: each node is the set of states one word
  // reaches, so distinct words are counted once even when G is non-deterministic.
  std::vector<StateSet> subsets{{g.initial_index()}};
  std::map<StateSet, int> subset_index{{subsets[0], 0}};
  std::vector<std::vector<int>> next_subset;  // [subset][event] -> subset or kNone
  const auto expand = [&](int id) {
    while (next_subset.size() <= at(id)) next_subset.emplace_back();
    if (!next_subset[at(id)].empty() || g.event_count() == 0) return;
    std::vector<int> row(at(g.event_count()), Generator::kNone);
    for (int e = 0; e < g.event_count(); ++e) {
      StateSet next = successors(g, subsets[at(id)], e);
      if (next.empty()) continue;
      auto [it, inserted] = subset_index.emplace(next, static_cast<int>(subsets.size()));
      if (inserted) subsets.push_back(std::move(next));
      row[at(e)] = it->second;
    }
    next_subset[at(id)] = std::move(row);
  };

  std::vector<std::uint64_t> count{1};
  result.words_per_length[0] = 1;
  result.marked_per_length[0] = any_marked(g, subsets[0]) ? 1 : 0;
  for (std::size_t length = 1; length <= n; ++length) {
    std::vector<std::uint64_t> next_count(subsets.size(), 0);
    for (std::size_t id = 0; id < count.size(); ++id) {
      if (count[id] == 0) continue;
      expand(static_cast<int>(id));
      next_count.resize(subsets.size(), 0);
      for (int target : next_subset[id]) {
        if (target == Generator::kNone) continue;
        next_count[at(target)] = saturating_add(next_count[at(target)], count[id], result.counts_saturated);
      }
    }
    for (std::size_t id = 0; id < next_count.size(); ++id) {
      result.words_per_length[length] =
          saturating_add(result.words_per_length[length], next_count[id], result.counts_saturated);
      if (any_marked(g, subsets[id]))
        result.marked_per_length[length] =
            saturating_add(result.marked_per_length[length], next_count[id], result.counts_saturated);
    }
    count = std::move(next_count);
  }

  // Listing, breadth first so words come by length then in event order. The frontier never holds
  // more than `limit` words.
  struct Partial {
    std::vector<int> events;
    int subset;
  };
  std::vector<Partial> frontier{{{}, 0}};
  for (std::size_t length = 1; length <= n && result.words.size() < limit; ++length) {
    std::vector<Partial> next_frontier;
    for (const auto& partial : frontier) {
      if (result.words.size() >= limit) break;
      expand(partial.subset);
      for (int e = 0; e < g.event_count() && result.words.size() < limit; ++e) {
        const int target = next_subset[at(partial.subset)][at(e)];
        if (target == Generator::kNone) continue;
        Partial extended{partial.events, target};
        extended.events.push_back(e);
        ListedWord word;
        for (int event : extended.events) word.events.push_back(g.events()[at(event)].id);
        word.marked = any_marked(g, subsets[at(target)]);
        word.reached = state_names(g, subsets[at(target)]);
        result.words.push_back(std::move(word));
        next_frontier.push_back(std::move(extended));
      }
    }
    frontier = std::move(next_frontier);
  }
  std::uint64_t total = 0;
  bool saturated = result.counts_saturated;
  for (std::size_t length = 1; length <= n; ++length)
    total = saturating_add(total, result.words_per_length[length], saturated);
  result.truncated = saturated || total > result.words.size();
  return result;
}

std::vector<std::string> accessible_states(const Generator& g) { return names_where(g, accessible_mask(g), true); }

std::vector<std::string> coaccessible_states(const Generator& g) { return names_where(g, coaccessible_mask(g), true); }

Generator accessible_part(const Generator& g) { return restrict_to(g, accessible_mask(g)); }

Generator coaccessible_part(const Generator& g) { return restrict_to(g, coaccessible_mask(g)); }

Generator trim(const Generator& g) {
  std::vector<char> keep = accessible_mask(g);
  const auto coacc = coaccessible_mask(g);
  for (std::size_t s = 0; s < keep.size(); ++s)
    if (coacc[s] == 0) keep[s] = 0;
  // Restricting to acc ∩ coacc is exact: a state on a path from s0 to S_M stays on it, because
  // every state along such a path is itself accessible and co-accessible.
  return restrict_to(g, keep);
}

AccessibilityCheck check_accessible(const Generator& g) { return {names_where(g, accessible_mask(g), false)}; }

CoaccessibilityCheck check_coaccessible(const Generator& g) { return {names_where(g, coaccessible_mask(g), false)}; }

DeterminismCheck check_deterministic(const Generator& g) {
  DeterminismCheck result;
  if (g.is_deterministic()) return result;
  for (int s = 0; s < g.state_count(); ++s) {
    std::map<int, std::vector<std::size_t>> by_event;  // ordered by event declaration
    for (int i : g.outgoing(s)) by_event[g.indexed_transitions()[at(i)].event].push_back(at(i));
    for (auto& [event, transitions] : by_event)
      if (transitions.size() > 1)
        result.choices.push_back({g.states()[at(s)].id, g.events()[at(event)].id, std::move(transitions)});
  }
  return result;
}

NonblockingCheck check_nonblocking(const Generator& g) {
  const auto acc = accessible_mask(g);
  const auto coacc = coaccessible_mask(g);
  NonblockingCheck result;
  std::vector<char> blocking(acc.size(), 0);
  for (std::size_t s = 0; s < acc.size(); ++s) {
    blocking[s] = static_cast<char>(acc[s] != 0 && coacc[s] == 0);
    if (blocking[s] != 0) result.blocking.push_back(g.states()[s].id);
  }
  for (std::size_t i = 0; i < g.indexed_transitions().size(); ++i) {
    const auto& edge = g.indexed_transitions()[i];
    if (acc[at(edge.from)] != 0 && blocking[at(edge.from)] == 0 && blocking[at(edge.to)] != 0)
      result.entering.push_back(i);
  }
  return result;
}

CheckReport check_all(const Generator& g) {
  return {check_accessible(g), check_coaccessible(g), check_deterministic(g), check_nonblocking(g)};
}

Generator compose(const Generator& g1, const Generator& g2, std::size_t max_states) {
  Generator out(g1.name() + "||" + g2.name(),
                fmt::format("synchronous composition of {} and {}", g1.name(), g2.name()));
  struct UnionEvent {
    int in1;
    int in2;
  };
  std::vector<UnionEvent> sigma;
  for (int e = 0; e < g1.event_count(); ++e) {
    const auto& event = g1.events()[at(e)];
    sigma.push_back({e, g2.event_index(event.id)});
    out.add_event(event.id, event.description, event.where);
  }
  for (int e = 0; e < g2.event_count(); ++e) {
    const auto& event = g2.events()[at(e)];
    if (g1.has_event(event.id)) continue;
    sigma.push_back({Generator::kNone, e});
    out.add_event(event.id, event.description, event.where);
  }
  if (g1.initial_index() == Generator::kNone || g2.initial_index() == Generator::kNone) return out;

  // Targets of one machine on one event, or "stay put" when the event is not in its alphabet.
  const auto moves = [](const Generator& g, int state, int event) {
    std::vector<int> targets;
    if (event == Generator::kNone) return std::vector<int>{state};
    for (int i : g.outgoing(state)) {
      const auto& edge = g.indexed_transitions()[at(i)];
      if (edge.event == event) targets.push_back(edge.to);
    }
    return targets;
  };

  using Pair = std::pair<int, int>;
  std::vector<Pair> pairs{{g1.initial_index(), g2.initial_index()}};
  std::map<Pair, int> pair_index{{pairs[0], 0}};
  struct ProductEdge {
    int from;
    std::size_t event;
    int to;
  };
  std::vector<ProductEdge> edges;
  for (std::size_t k = 0; k < pairs.size(); ++k) {  // breadth first: `pairs` grows as we go
    const auto [a, b] = pairs[k];
    for (std::size_t u = 0; u < sigma.size(); ++u) {
      for (int a2 : moves(g1, a, sigma[u].in1))
        for (int b2 : moves(g2, b, sigma[u].in2)) {
          auto [it, inserted] = pair_index.emplace(Pair{a2, b2}, static_cast<int>(pairs.size()));
          if (inserted) pairs.emplace_back(a2, b2);
          edges.push_back({static_cast<int>(k), u, it->second});
          if (pairs.size() > max_states || edges.size() > 10 * max_states)
            throw UsageError(
                fmt::format("fsm: the composition of {} and {} has more than {} states or {} transitions; "
                            "--max-states raises the limit",
                            g1.name(), g2.name(), max_states, 10 * max_states));
        }
    }
  }

  std::vector<std::string> names;
  std::set<std::string> taken;
  for (const auto& [a, b] : pairs) {
    const auto& s1 = g1.states()[at(a)];
    const auto& s2 = g2.states()[at(b)];
    std::string name = s1.id + "|" + s2.id;
    if (!taken.insert(name).second)
      throw Error(fmt::format("fsm: composing {} and {} gives two states named '{}'", g1.name(), g2.name(), name));
    std::string description;
    if (!s1.description.empty() || !s2.description.empty())
      description =
          (s1.description.empty() ? s1.id : s1.description) + " | " + (s2.description.empty() ? s2.id : s2.description);
    out.add_state(name, std::move(description));
    names.push_back(std::move(name));
  }
  for (const auto& edge : edges)
    out.add_transition(names[at(edge.from)], out.events()[edge.event].id, names[at(edge.to)]);
  out.set_initial(names[0]);
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (g1.is_marked(pairs[k].first) && g2.is_marked(pairs[k].second)) out.mark(names[k]);
  return out;
}

TransitionCoverage transition_coverage(const Generator& g, const std::vector<std::vector<std::string>>& traces) {
  TransitionCoverage result;
  result.counts.assign(g.transitions().size(), 0);
  result.traces = traces.size();
  for (std::size_t i = 0; i < traces.size(); ++i) {
    auto evaluation = evaluate_word(g, traces[i]);
    if (!evaluation.generated) {
      result.rejected.push_back({i, std::move(evaluation)});
      continue;
    }
    ++result.accepted;
    std::vector<int> events;
    events.reserve(traces[i].size());
    for (const auto& e : traces[i]) events.push_back(g.event_index(e));
    for (int t : witness_path(g, events)) ++result.counts[at(t)];
  }
  result.covered = static_cast<std::size_t>(
      std::count_if(result.counts.begin(), result.counts.end(), [](std::size_t c) { return c > 0; }));
  return result;
}

}  // namespace emrm::fsm
