// `emrm fsm FSM.yaml`: loads a generator, optionally composes it with another, runs the requested
// operations (fsm::make_report), writes the diagrams and prints the report (fsm::to_text or
// fsm::to_json). Exit 1 when a check fails or a trace is not in L(G); bad input escapes as
// emrm::InputError (exit 2).

#include <fmt/format.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/fsm/dot.hpp"
#include "emrm/fsm/generator.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/fsm/report.hpp"

namespace emrm::cli {
namespace {

constexpr int kMaxWordLength = 20;

struct FsmOptions {
  std::string file;
  bool check = false;
  int words = -1;  // -1: not asked
  std::vector<std::string> word_queries;
  std::string traces;
  std::string compose;
  std::size_t max_states = fsm::kDefaultMaxComposedStates;
  std::string dot;
  std::string svg;
  std::string format = "text";
};

int run_fsm(const FsmOptions& options) {
  fsm::Generator g = fsm::load_generator(options.file);
  std::string source = options.file;
  if (!options.compose.empty()) {
    g = fsm::compose(g, fsm::load_generator(options.compose), options.max_states);
    source = options.file + " || " + options.compose;
  }
  // Read every input before writing anything, so a bad trace file leaves no half-written output.
  fsm::ReportRequest request;
  request.check = options.check;
  request.words_max_length = options.words;
  request.word_queries = options.word_queries;
  if (!options.traces.empty()) request.traces = fsm::TraceFile{options.traces, fsm::load_traces(options.traces)};

  fsm::Report report = fsm::make_report(std::move(g), std::move(source), request);
  if (!options.dot.empty() || !options.svg.empty()) {
    // Rendered before either file is written, then both or neither: a missing Graphviz leaves no
    // --dot file behind.
    const std::string dot = fsm::diagram_dot(report);
    std::vector<core::FileContent> files;
    if (!options.dot.empty()) files.push_back({options.dot, dot});
    if (!options.svg.empty()) files.push_back({options.svg, fsm::render_svg(dot)});
    core::write_files(files);
    for (const auto& f : files) report.written.push_back(f.path.string());
  }
  if (options.format == "json")
    fmt::print("{}\n", fsm::to_json(report).dump(2));
  else
    fmt::print("{}", fsm::to_text(report));
  return static_cast<int>(report.ok() ? ExitCode::kSuccess : ExitCode::kFindings);
}

}  // namespace

void register_fsm_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<FsmOptions>();
  CLI::App* cmd =
      app.add_subcommand("fsm",
                         "Check and explore a hazard-loss FSM G = (S, Σ, δ, s0, S_M) (docs/fsm.md).\n"
                         "Without options prints a summary. Exit 1 if a check fails or a trace is not in L(G).");
  cmd->add_option("FSM", options->file, "FSM YAML file (schema in docs/fsm.md)")->required()->type_name("FILE");
  cmd->add_flag("--check", options->check,
                "Check that G is accessible, co-accessible, deterministic and non-blocking (exit 1 if not)");
  cmd->add_option("--words", options->words,
                  fmt::format("List the words of L(G) of length 1..N (0..{}), marking those in L_m(G)", kMaxWordLength))
      ->check(CLI::Range(0, kMaxWordLength))
      ->type_name("N");
  cmd->add_option("--word", options->word_queries,
                  "Is this word (events separated by spaces, quoted) in L(G) and L_m(G)? Repeatable")
      ->expected(1)
      ->take_all()
      ->type_name("WORD");
  cmd->add_option("--traces", options->traces,
                  "Transition coverage of the traces in FILE (one per line, events separated by spaces, '#' comments)")
      ->type_name("FILE");
  cmd->add_option("--compose", options->compose,
                  "Work on the synchronous composition G || OTHER (another FSM YAML file)")
      ->type_name("OTHER");
  cmd->add_option("--max-states", options->max_states, "With --compose: most states of the product")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100'000'000}))
      ->capture_default_str();
  cmd->add_option("--dot", options->dot, "Write the Graphviz DOT diagram to FILE (edges coloured by --traces)")
      ->type_name("FILE");
  cmd->add_option("--svg", options->svg, "Render the diagram to FILE as SVG (needs Graphviz `dot`)")->type_name("FILE");
  cmd->add_option("--format", options->format, "Output format: text or json")->check(CLI::IsMember({"text", "json"}));
  cmd->callback([options, &exit_code] { exit_code = run_fsm(*options); });
}

}  // namespace emrm::cli
