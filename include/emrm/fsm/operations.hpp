#pragma once

// Operations on generators (Cassandras & Lafortune, ch. 2): membership of a word, bounded
// enumeration of L(G), accessible / co-accessible parts, trim, the structural checks the
// `emrm fsm --check` command runs, synchronous composition and transition coverage of traces.
//
// Every function is pure: it reads its arguments and returns a value. Check results are plain
// structs that name the states, events and transitions at fault; a failed check is a value, never
// an exception.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/fsm/generator.hpp"

namespace emrm::fsm {

/// A word (string of events) as written on a command line or in a trace file: event ids
/// separated by white space. An empty or blank text is the empty word ε.
[[nodiscard]] std::vector<std::string> split_word(std::string_view text);

// ---- membership -----------------------------------------------------------------------------

/// What happened when G read one word from s0.
struct WordEvaluation {
  bool generated = false;            ///< word ∈ L(G)
  bool marked = false;               ///< word ∈ L_m(G)
  std::vector<std::string> reached;  ///< δ*(s0, word): one state, several on a non-deterministic G
  // When the word is not generated:
  std::size_t failed_at = 0;             ///< 1-based position of the event G could not take (0: no s0)
  std::string failed_event;              ///< that event
  bool unknown_event = false;            ///< the event is not in Σ at all
  std::vector<std::string> failed_from;  ///< the state(s) G was in when it could not take it
};

/// Reads `word` from s0 over every path (so it is exact on non-deterministic machines too).
[[nodiscard]] WordEvaluation evaluate_word(const Generator& g, const std::vector<std::string>& word);

/// The run of a deterministic G on `word` from s0, as s0 e1 s1 e2 s2 …; it stops where δ is
/// undefined (so a complete run has 2·|word| + 1 entries) and is empty without s0.
[[nodiscard]] std::vector<std::string> trace_word(const Generator& g, const std::vector<std::string>& word);

// ---- bounded enumeration of L(G) ----------------------------------------------------------

/// One listed word of L(G).
struct ListedWord {
  std::vector<std::string> events;
  bool marked = false;               ///< ∈ L_m(G)
  std::vector<std::string> reached;  ///< δ*(s0, word)
};

/// The words of L(G) of length 0..max_length.
struct WordEnumeration {
  int max_length = 0;
  /// Number of distinct words of each length 0..max_length (index = length). Saturates at
  /// UINT64_MAX, in which case counts_saturated is set.
  std::vector<std::uint64_t> words_per_length;
  /// Of those, the words in L_m(G).
  std::vector<std::uint64_t> marked_per_length;
  bool counts_saturated = false;
  /// The words of length 1..max_length, by length, then by event order (Σ's declaration order,
  /// lexicographically). Only the first `limit` words when `truncated`.
  std::vector<ListedWord> words;
  bool truncated = false;
};

/// Enumerates L(G) up to `max_length` events, listing at most `limit` words (the counts are exact
/// regardless). ε counts as the single word of length 0 when G has an initial state. Distinct words
/// are counted, so a non-deterministic G does not count a word twice. Throws emrm::Error if
/// max_length < 0.
[[nodiscard]] WordEnumeration enumerate_words(const Generator& g, int max_length, std::size_t limit = 10'000);

// ---- accessibility ----------------------------------------------------------------------------

/// States reachable from s0 (in state order); empty if G has no initial state.
[[nodiscard]] std::vector<std::string> accessible_states(const Generator& g);
/// States from which some marked state is reachable (in state order).
[[nodiscard]] std::vector<std::string> coaccessible_states(const Generator& g);

/// Ac(G): G restricted to its accessible states (events, names and orders kept).
[[nodiscard]] Generator accessible_part(const Generator& g);
/// CoAc(G): G restricted to its co-accessible states; s0 is dropped (L = ∅) if it is not co-accessible.
[[nodiscard]] Generator coaccessible_part(const Generator& g);
/// Trim(G) = Ac(CoAc(G)) = CoAc(Ac(G)): accessible and co-accessible.
[[nodiscard]] Generator trim(const Generator& g);

// ---- checks ---------------------------------------------------------------------------------

/// G is accessible: every state is reachable from s0.
struct AccessibilityCheck {
  std::vector<std::string> unreachable;
  [[nodiscard]] bool ok() const noexcept { return unreachable.empty(); }
};

/// G is co-accessible: every state can reach a marked state.
struct CoaccessibilityCheck {
  std::vector<std::string> cannot_reach_marked;
  [[nodiscard]] bool ok() const noexcept { return cannot_reach_marked.empty(); }
};

/// A state and an event on which δ has several targets.
struct NondeterministicChoice {
  std::string state;
  std::string event;
  std::vector<std::size_t> transitions;  ///< indices into g.transitions(), in file order
};

/// G is deterministic: δ has at most one target per (state, event).
struct DeterminismCheck {
  std::vector<NondeterministicChoice> choices;
  [[nodiscard]] bool ok() const noexcept { return choices.empty(); }
};

/// G is non-blocking: every accessible state is co-accessible, i.e. the prefix closure of L_m(G) is
/// L(G) and no reachable state is a dead end or a livelock away from S_M.
struct NonblockingCheck {
  std::vector<std::string> blocking;  ///< accessible states that cannot reach a marked state
  /// Transitions from an accessible, co-accessible state into a blocking state: the steps after
  /// which G can no longer complete a task (indices into g.transitions()).
  std::vector<std::size_t> entering;
  [[nodiscard]] bool ok() const noexcept { return blocking.empty(); }
};

[[nodiscard]] AccessibilityCheck check_accessible(const Generator& g);
[[nodiscard]] CoaccessibilityCheck check_coaccessible(const Generator& g);
[[nodiscard]] DeterminismCheck check_deterministic(const Generator& g);
[[nodiscard]] NonblockingCheck check_nonblocking(const Generator& g);

/// All four checks of `emrm fsm --check`.
struct CheckReport {
  AccessibilityCheck accessible;
  CoaccessibilityCheck coaccessible;
  DeterminismCheck deterministic;
  NonblockingCheck nonblocking;
  [[nodiscard]] bool ok() const noexcept {
    return accessible.ok() && coaccessible.ok() && deterministic.ok() && nonblocking.ok();
  }
};
[[nodiscard]] CheckReport check_all(const Generator& g);

// ---- composition ------------------------------------------------------------------------------

/// Synchronous (parallel) composition G1 || G2: Σ = Σ1 ∪ Σ2 (G1's events first); an event in both
/// alphabets moves both machines together, an event in only one moves that machine alone. States
/// are pairs named "s1|s2", only the accessible ones, in breadth-first order from (s01, s02); a pair
/// is marked when both halves are. The result is named "G1||G2". If either has no initial state the
/// result has no states. Throws emrm::Error if two pairs would get the same name (possible only when
/// ids themselves contain '|'); throws emrm::UsageError when the product has more than
/// `max_states` accessible states or ten times as many transitions (two machines of a thousand
/// states each could otherwise take gigabytes).
inline constexpr std::size_t kDefaultMaxComposedStates = 100'000;
[[nodiscard]] Generator compose(const Generator& g1, const Generator& g2,
                                std::size_t max_states = kDefaultMaxComposedStates);

// ---- coverage -----------------------------------------------------------------------------

/// A trace that G cannot generate.
struct RejectedTrace {
  std::size_t trace = 0;      ///< index into the traces given
  WordEvaluation evaluation;  ///< where and why it failed
};

/// Which transitions a set of traces exercised.
struct TransitionCoverage {
  std::vector<std::size_t> counts;  ///< per transition of g.transitions(): how many times taken
  std::size_t covered = 0;          ///< transitions taken at least once
  std::size_t traces = 0;           ///< traces given
  std::size_t accepted = 0;         ///< traces in L(G)
  std::vector<RejectedTrace> rejected;
  /// covered / |transitions| (1 for a machine without transitions).
  [[nodiscard]] double fraction() const noexcept {
    return counts.empty() ? 1.0 : static_cast<double>(covered) / static_cast<double>(counts.size());
  }
};

/// Runs every trace from s0 and counts the transitions taken. A trace that is not in L(G) is
/// reported in `rejected` and contributes no counts: its prefix describes behaviour the model does
/// not explain, so it is not evidence that a transition was tested. On a non-deterministic G the
/// counted path is the first one, in transition declaration order, that reads the whole trace.
[[nodiscard]] TransitionCoverage transition_coverage(const Generator& g,
                                                     const std::vector<std::vector<std::string>>& traces);

}  // namespace emrm::fsm
