// The report of `emrm fsm` (and of reproduce's FSM checks): the requested operations on one
// machine, and its text and JSON forms.

#include "emrm/fsm/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include "emrm/core/text.hpp"
#include "emrm/fsm/dot.hpp"

namespace emrm::fsm {
namespace {

using Json = nlohmann::ordered_json;

std::string transition_text(const Transition& t) { return fmt::format("{} --{}--> {}", t.from, t.event, t.to); }

std::string with_location(const Transition& t) {
  if (t.where.file.empty()) return transition_text(t);
  return fmt::format("{} ({})", transition_text(t), t.where.str());
}

std::string word_text(const std::vector<std::string>& word) { return core::join(word, " "); }

std::string states_text(const std::vector<std::string>& states) {
  return states.size() == 1 ? states[0] : "{" + core::join(states, ", ") + "}";
}

std::string plural(std::uint64_t n, std::string_view one, std::string_view many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

/// Why a word is not in L(G), in one phrase.
std::string failure_text(const WordEvaluation& e) {
  if (e.failed_at == 0) return "the machine has no initial state";
  if (e.unknown_event)
    return fmt::format("'{}' (event {}) is not an event of the machine", e.failed_event, e.failed_at);
  return fmt::format("no transition on '{}' (event {}) from {}", e.failed_event, e.failed_at,
                     states_text(e.failed_from));
}

// ---- text output --------------------------------------------------------------------------

std::string summary_text(const Generator& g, const std::string& source) {
  std::string out = fmt::format(
      "{} ({}): {}, {}, {}, {}\n", g.name(), source, plural(g.states().size(), "state", "states"),
      plural(g.events().size(), "event", "events"), plural(g.transitions().size(), "transition", "transitions"),
      g.is_deterministic() ? "deterministic" : "non-deterministic");
  out += fmt::format("initial: {}\n", g.initial().value_or("(none)"));
  const auto marked = g.marked_states();
  out += fmt::format("marked:  {}\n", marked.empty() ? "(none)" : core::join(marked, ", "));
  std::size_t width = 0;
  for (const auto& s : g.states()) width = std::max(width, s.id.size());
  out += "states:\n";
  for (const auto& s : g.states()) {
    std::vector<std::string> tags;
    if (g.initial() == s.id) tags.emplace_back("initial");
    if (g.is_marked(s.id)) tags.emplace_back("marked");
    out += fmt::format("  {:<{}}  {}{}\n", s.id, width, s.description,
                       tags.empty() ? "" : fmt::format("  [{}]", core::join(tags, ", ")));
  }
  width = 0;
  for (const auto& e : g.events()) width = std::max(width, e.id.size());
  out += "events:\n";
  for (const auto& e : g.events()) out += fmt::format("  {:<{}}  {}\n", e.id, width, e.description);
  out += "transitions:\n";
  for (const auto& t : g.transitions()) out += fmt::format("  {}\n", transition_text(t));
  return out;
}

std::string check_text(const Generator& g, const CheckReport& r) {
  const auto line = [](std::string_view what, bool ok, const std::string& detail) {
    return fmt::format("  {:<15} {}\n", std::string(what) + ":", ok ? std::string("ok") : "FAILED: " + detail);
  };
  std::string out = fmt::format("checks of {}:\n", g.name());
  out += line("accessible", r.accessible.ok(),
              fmt::format("not reachable from {}: {}", g.initial().value_or("(no initial state)"),
                          core::join(r.accessible.unreachable, ", ")));
  out += line("co-accessible", r.coaccessible.ok(),
              fmt::format("cannot reach a marked state: {}", core::join(r.coaccessible.cannot_reach_marked, ", ")));
  std::vector<std::string> choices;
  for (const auto& c : r.deterministic.choices) {
    std::vector<std::string> targets;
    for (std::size_t i : c.transitions) {
      const auto& t = g.transitions()[i];
      targets.push_back(t.where.file.empty() ? t.to : fmt::format("{} ({})", t.to, t.where.str()));
    }
    choices.push_back(fmt::format("{} on '{}' goes to {}", c.state, c.event, core::join(targets, " or ")));
  }
  out += line("deterministic", r.deterministic.ok(), core::join(choices, "; "));
  std::vector<std::string> entering;
  for (std::size_t i : r.nonblocking.entering) entering.push_back(with_location(g.transitions()[i]));
  out += line(
      "non-blocking", r.nonblocking.ok(),
      fmt::format("blocking (reachable, cannot reach a marked state): {}{}", core::join(r.nonblocking.blocking, ", "),
                  entering.empty() ? "" : "; entered by " + core::join(entering, ", ")));
  return out;
}

std::string words_text(const WordEnumeration& w) {
  std::string out = fmt::format("words of L(G) of length 1..{} (\"marked\": also in L_m(G)):\n", w.max_length);
  std::size_t next = 0;
  for (int length = 1; length <= w.max_length; ++length) {
    const auto n = w.words_per_length[static_cast<std::size_t>(length)];
    const auto m = w.marked_per_length[static_cast<std::size_t>(length)];
    out += fmt::format("  length {}: {}, {} in L_m(G)\n", length, plural(n, "word", "words"), m);
    for (; next < w.words.size() && w.words[next].events.size() == static_cast<std::size_t>(length); ++next) {
      const auto& word = w.words[next];
      out += fmt::format("    {} -> {}{}\n", word_text(word.events), states_text(word.reached),
                         word.marked ? " (marked)" : "");
    }
  }
  if (w.truncated)
    out += fmt::format("  (listing stopped after {} words; the counts per length are exact{})\n", w.words.size(),
                       w.counts_saturated ? " up to the saturated ones, shown as 18446744073709551615" : "");
  return out;
}

std::string word_query_text(const std::string& text, const WordEvaluation& e) {
  const std::string word = text.empty() ? "word \"\" (the empty word)" : fmt::format("word \"{}\"", text);
  if (e.generated)
    return fmt::format("{}: in L(G), {} L_m(G); reaches {}\n", word, e.marked ? "in" : "not in",
                       states_text(e.reached));
  return fmt::format("{}: not in L(G): {}\n", word, failure_text(e));
}

std::string coverage_text(const Generator& g, const TransitionCoverage& c, const std::vector<Trace>& traces,
                          const std::string& file) {
  std::string out = fmt::format("transition coverage of {} from {} ({} in L(G), {} rejected):\n",
                                plural(c.traces, "trace", "traces"), file, c.accepted, c.rejected.size());
  out += fmt::format("  {} of {} transitions covered ({:.1f} %)\n", c.covered, c.counts.size(), 100.0 * c.fraction());
  if (!g.is_deterministic())
    out += "  note: the machine is non-deterministic; each trace counts its first path in file order\n";
  for (std::size_t i = 0; i < c.counts.size(); ++i)
    out += fmt::format("  {:>8}  {}{}\n", c.counts[i], transition_text(g.transitions()[i]),
                       c.counts[i] == 0 ? "  (not covered)" : "");
  if (!c.rejected.empty()) {
    out += "rejected traces (not in L(G)):\n";
    for (const auto& r : c.rejected)
      out += fmt::format("  {}: \"{}\": {}\n", traces[r.trace].where.str(), word_text(traces[r.trace].events),
                         failure_text(r.evaluation));
  }
  return out;
}

// ---- JSON output --------------------------------------------------------------------------

Json transition_json(const Transition& t) {
  Json j{{"from", t.from}, {"event", t.event}, {"to", t.to}};
  if (!t.where.file.empty()) j["location"] = t.where.str();
  return j;
}

Json summary_json(const Generator& g, const std::string& source) {
  Json states = Json::array();
  for (const auto& s : g.states())
    states.push_back({{"id", s.id},
                      {"description", s.description},
                      {"initial", g.initial() == s.id},
                      {"marked", g.is_marked(s.id)}});
  Json events = Json::array();
  for (const auto& e : g.events()) events.push_back({{"id", e.id}, {"description", e.description}});
  Json transitions = Json::array();
  for (const auto& t : g.transitions()) transitions.push_back(transition_json(t));
  return {{"name", g.name()},
          {"source", source},
          {"description", g.description()},
          {"deterministic", g.is_deterministic()},
          {"initial", g.initial() ? Json(*g.initial()) : Json(nullptr)},
          {"marked", g.marked_states()},
          {"states", states},
          {"events", events},
          {"transitions", transitions}};
}

Json check_json(const Generator& g, const CheckReport& r) {
  Json choices = Json::array();
  for (const auto& c : r.deterministic.choices) {
    Json transitions = Json::array();
    for (std::size_t i : c.transitions) transitions.push_back(transition_json(g.transitions()[i]));
    choices.push_back({{"state", c.state}, {"event", c.event}, {"transitions", transitions}});
  }
  Json entering = Json::array();
  for (std::size_t i : r.nonblocking.entering) entering.push_back(transition_json(g.transitions()[i]));
  return {{"ok", r.ok()},
          {"accessible", {{"ok", r.accessible.ok()}, {"unreachable", r.accessible.unreachable}}},
          {"coaccessible", {{"ok", r.coaccessible.ok()}, {"cannot_reach_marked", r.coaccessible.cannot_reach_marked}}},
          {"deterministic", {{"ok", r.deterministic.ok()}, {"choices", choices}}},
          {"nonblocking", {{"ok", r.nonblocking.ok()}, {"blocking", r.nonblocking.blocking}, {"entering", entering}}}};
}

Json evaluation_json(const WordEvaluation& e) {
  Json j{{"generated", e.generated}, {"marked", e.marked}, {"reached", e.reached}};
  if (!e.generated)
    j["failure"] = {{"position", e.failed_at},
                    {"event", e.failed_event},
                    {"unknown_event", e.unknown_event},
                    {"from", e.failed_from},
                    {"message", failure_text(e)}};
  return j;
}

Json words_json(const WordEnumeration& w) {
  Json counts = Json::array();
  for (std::size_t length = 0; length < w.words_per_length.size(); ++length)
    counts.push_back(
        {{"length", length}, {"words", w.words_per_length[length]}, {"marked", w.marked_per_length[length]}});
  Json list = Json::array();
  for (const auto& word : w.words)
    list.push_back({{"word", word_text(word.events)}, {"marked", word.marked}, {"reached", word.reached}});
  return {{"max_length", w.max_length},
          {"counts", counts},
          {"counts_saturated", w.counts_saturated},
          {"truncated", w.truncated},
          {"list", list}};
}

Json coverage_json(const Generator& g, const TransitionCoverage& c, const std::vector<Trace>& traces,
                   const std::string& file) {
  Json counts = Json::array();
  for (std::size_t i = 0; i < c.counts.size(); ++i) {
    Json t = transition_json(g.transitions()[i]);
    t["count"] = c.counts[i];
    counts.push_back(std::move(t));
  }
  Json rejected = Json::array();
  for (const auto& r : c.rejected) {
    Json j{{"location", traces[r.trace].where.str()}, {"trace", word_text(traces[r.trace].events)}};
    j.update(evaluation_json(r.evaluation));
    rejected.push_back(std::move(j));
  }
  return {
      {"file", file},         {"traces", c.traces},       {"accepted", c.accepted}, {"transitions", c.counts.size()},
      {"covered", c.covered}, {"fraction", c.fraction()}, {"counts", counts},       {"rejected", rejected}};
}

}  // namespace

Report make_report(Generator machine, std::string source, const ReportRequest& request) {
  Report report{std::move(machine), std::move(source), {}, {}, {}, {}, {}};
  const Generator& g = report.machine;
  if (request.check) report.check = check_all(g);
  if (request.words_max_length >= 0)
    report.words = enumerate_words(g, request.words_max_length, request.max_listed_words);
  for (const auto& query : request.word_queries) {
    const auto word = split_word(query);
    report.word_queries.push_back({word_text(word), evaluate_word(g, word)});
  }
  if (request.traces) {
    std::vector<std::vector<std::string>> words;
    words.reserve(request.traces->traces.size());
    for (const auto& t : request.traces->traces) words.push_back(t.events);
    report.coverage = TraceCoverageReport{*request.traces, transition_coverage(g, words)};
  }
  return report;
}

nlohmann::ordered_json to_json(const Report& report) {
  const Generator& g = report.machine;
  Json out{{"fsm", summary_json(g, report.source)}};
  if (report.check) out["check"] = check_json(g, *report.check);
  if (report.words) out["words"] = words_json(*report.words);
  if (!report.word_queries.empty()) {
    Json queries = Json::array();
    for (const auto& query : report.word_queries) {
      Json j{{"word", query.word}};
      j.update(evaluation_json(query.evaluation));
      queries.push_back(std::move(j));
    }
    out["word_queries"] = queries;
  }
  if (report.coverage)
    out["coverage"] =
        coverage_json(g, report.coverage->coverage, report.coverage->traces.traces, report.coverage->traces.file);
  out["written"] = report.written;
  return out;
}

std::string to_text(const Report& report) {
  const Generator& g = report.machine;
  std::string text;
  if (!report.has_operations()) text += summary_text(g, report.source);
  if (report.check) text += check_text(g, *report.check);
  if (report.words) text += words_text(*report.words);
  for (const auto& query : report.word_queries) text += word_query_text(query.word, query.evaluation);
  if (report.coverage)
    text += coverage_text(g, report.coverage->coverage, report.coverage->traces.traces, report.coverage->traces.file);
  for (const auto& path : report.written) text += fmt::format("wrote {}\n", path);
  return text;
}

std::string diagram_dot(const Report& report) {
  DotOptions options;
  if (report.coverage) options.transition_counts = report.coverage->coverage.counts;
  return to_dot(report.machine, options);
}

Report write_check_files(const std::filesystem::path& fsm_file, const std::filesystem::path& dir) {
  ReportRequest request;
  request.check = true;
  Report report = make_report(load_generator(fsm_file), fsm_file.string(), request);
  const std::string stem = fsm_file.stem().string();
  const std::string dot = to_dot(report.machine);
  std::vector<core::FileContent> files{{dir / (stem + "_check.json"), to_json(report).dump(2) + "\n"},
                                       {dir / (stem + "_plain.dot"), dot}};
  if (dot_available()) files.push_back({dir / (stem + "_plain.svg"), render_svg(dot)});
  core::write_files(files);  // rendered first, then all or none
  return report;
}

}  // namespace emrm::fsm
