#pragma once

// A generator in the discrete-event-system sense (Cassandras & Lafortune; paper §III-C, Step 5):
// G = (S, Σ, δ, s0, S_M) with a partial transition function δ : S × Σ → S extended to words.
//
// L(G)   = { w ∈ Σ* | δ*(s0, w) is defined }            (the words G can generate)
// L_m(G) = { w ∈ L(G) | δ*(s0, w) ∈ S_M }               (the words that end in a marked state)
//
// A Generator can also hold a *non-deterministic* machine (two transitions with the same state
// and event but different targets) so that a file written that way loads and the determinism check
// can name the offending pair instead of the loader silently picking one. See step() and
// generates() for what each query means on such a machine.
//
// States and events are indexed by int internally; the *_index() functions expose those indices
// for callers that step a machine many times (the simulator steps it once per scenario event).

#include <cassert>
#include <cstddef>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "emrm/core/error.hpp"

namespace emrm::fsm {

/// One state of S, with an optional human description (shown in reports and diagrams).
struct State {
  std::string id;
  std::string description;
  SourceLocation where;  ///< where it was declared; empty for machines built in code
};

/// One event of Σ.
struct Event {
  std::string id;
  std::string description;
  SourceLocation where;
};

/// One element of δ: from --event--> to.
struct Transition {
  std::string from;
  std::string event;
  std::string to;
  SourceLocation where;
  /// "S3 -execute_maneuver-> S4", as core::TransitionRef::str() writes a reference to it.
  [[nodiscard]] std::string str() const { return from + " -" + event + "-> " + to; }
};

/// A transition by index into states() / events().
struct IndexedTransition {
  int from = 0;
  int event = 0;
  int to = 0;
};

/// G = (S, Σ, δ, s0, S_M). Built incrementally (states, events, transitions, initial, marked);
/// states, events and transitions keep their insertion order, which every listing follows.
/// Copyable, no shared state; const member functions are safe to call from several threads.
class Generator {
 public:
  /// The index value meaning "no state" / "undefined".
  static constexpr int kNone = -1;

  Generator() = default;
  explicit Generator(std::string name, std::string description = {});

  // ---- building ----------------------------------------------------------------------------
  // Building is for loaders and operations that have already validated their input: misuse is a
  // programming error and throws emrm::Error (the YAML loader reports the same problems as
  // InputError with a file location before it ever calls these).

  /// Adds a state to S. Throws emrm::Error if `id` is empty or already a state.
  void add_state(std::string id, std::string description = {}, SourceLocation where = {});
  /// Adds an event to Σ. Throws emrm::Error if `id` is empty or already an event.
  void add_event(std::string id, std::string description = {}, SourceLocation where = {});
  /// Adds from --event--> to to δ. A second transition with the same `from` and `event` but another
  /// `to` is kept (the machine becomes non-deterministic). Throws emrm::Error if a name is unknown
  /// or the identical transition already exists.
  void add_transition(const std::string& from, const std::string& event, const std::string& to,
                      SourceLocation where = {});
  /// Sets s0. Throws emrm::Error if `state` is unknown.
  void set_initial(const std::string& state);
  /// Adds `state` to S_M (idempotent). Throws emrm::Error if `state` is unknown.
  void mark(const std::string& state);

  // ---- the tuple ---------------------------------------------------------------------------
  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] const std::string& description() const noexcept { return description_; }
  [[nodiscard]] const std::vector<State>& states() const noexcept { return states_; }
  [[nodiscard]] const std::vector<Event>& events() const noexcept { return events_; }
  [[nodiscard]] const std::vector<Transition>& transitions() const noexcept { return transitions_; }
  [[nodiscard]] const std::vector<IndexedTransition>& indexed_transitions() const noexcept { return edges_; }
  /// s0, or nothing for a generator whose initial state was never set (then L(G) = ∅).
  [[nodiscard]] std::optional<std::string> initial() const;
  /// S_M in state order.
  [[nodiscard]] std::vector<std::string> marked_states() const;

  [[nodiscard]] bool has_state(const std::string& id) const { return state_index_.contains(id); }
  [[nodiscard]] bool has_event(const std::string& id) const { return event_index_.contains(id); }
  /// True when from --event--> to is one of the transitions.
  [[nodiscard]] bool has_transition(const std::string& from, const std::string& event, const std::string& to) const;
  /// True when `state` is a state in S_M (false for unknown names).
  [[nodiscard]] bool is_marked(const std::string& state) const;
  /// True when no state has two transitions on the same event.
  [[nodiscard]] bool is_deterministic() const noexcept { return nondeterministic_pairs_ == 0; }

  // ---- δ and the languages -----------------------------------------------------------------

  /// δ(state, event): the next state, or nothing if δ is undefined there or a name is unknown.
  /// On a non-deterministic pair this is the target of the first transition added (file order).
  [[nodiscard]] std::optional<std::string> step(const std::string& state, const std::string& event) const;
  /// δ*(state, word), with δ*(s, ε) = s; nothing as soon as one step is undefined. Same rule as
  /// step() on non-deterministic pairs.
  [[nodiscard]] std::optional<std::string> run(const std::string& state, const std::vector<std::string>& word) const;
  /// word ∈ L(G). On a non-deterministic machine: some path from s0 reads the whole word.
  [[nodiscard]] bool generates(const std::vector<std::string>& word) const;
  /// word ∈ L_m(G). On a non-deterministic machine: some path from s0 reads it and ends marked.
  [[nodiscard]] bool marks(const std::vector<std::string>& word) const;

  // ---- indexed access (fast paths) ---------------------------------------------------------
  // Indices passed in must be valid (0 <= index < count); that is asserted, not checked.

  [[nodiscard]] int state_count() const noexcept { return static_cast<int>(states_.size()); }
  [[nodiscard]] int event_count() const noexcept { return static_cast<int>(events_.size()); }
  /// Index of a state / event, or kNone.
  [[nodiscard]] int state_index(const std::string& id) const;
  [[nodiscard]] int event_index(const std::string& id) const;
  /// s0 as an index, or kNone.
  [[nodiscard]] int initial_index() const noexcept { return initial_; }
  [[nodiscard]] bool is_marked(int state) const { return marked_[static_cast<std::size_t>(state)] != 0; }
  /// δ by index: the next state or kNone. `state` and `event` must be valid indices. O(1).
  [[nodiscard]] int step_index(int state, int event) const {
    const int t = delta_[slot(state, event)];
    return t == kNone ? kNone : edges_[static_cast<std::size_t>(t)].to;
  }
  /// The index (into transitions()) of the transition δ takes from `state` on `event`, or kNone. O(1).
  [[nodiscard]] int transition_index(int state, int event) const { return delta_[slot(state, event)]; }
  /// Indices (into transitions()) of every transition leaving `state`, in insertion order.
  [[nodiscard]] const std::vector<int>& outgoing(int state) const { return outgoing_[static_cast<std::size_t>(state)]; }

 private:
  [[nodiscard]] std::size_t slot(int state, int event) const {
    assert(state >= 0 && state < state_count() && event >= 0 && event < event_count());
    return static_cast<std::size_t>(state) * events_.size() + static_cast<std::size_t>(event);
  }
  /// The set of states reachable from s0 by `word` over every path (empty once a step fails).
  [[nodiscard]] std::vector<int> reach(const std::vector<std::string>& word) const;

  std::string name_;
  std::string description_;
  std::vector<State> states_;
  std::vector<Event> events_;
  std::vector<Transition> transitions_;
  std::vector<IndexedTransition> edges_;  // same order as transitions_
  std::unordered_map<std::string, int> state_index_;
  std::unordered_map<std::string, int> event_index_;
  std::vector<int> delta_;                  // |S|·|Σ| table of the first transition index, or kNone
  std::vector<std::vector<int>> outgoing_;  // per state, transition indices
  std::vector<char> marked_;                // per state
  int initial_ = kNone;
  int nondeterministic_pairs_ = 0;  // transitions that are not the first on their (state, event)
};

}  // namespace emrm::fsm
