// `emrm ca`: covering arrays from level counts or a PICT-style model (docs/covering-arrays.md).

#include <fmt/format.h>

#include <chrono>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/scenario/covering_array.hpp"
#include "emrm/scenario/covering_array_io.hpp"
#include "emrm/scenario/pict_model.hpp"
#include "options.hpp"

namespace emrm::cli {
namespace {

struct CaOptions {
  std::string model_file;
  std::string levels;
  int strength = 2;
  std::uint64_t seed = 1;
  double effort = scenario::CoveringArrayOptions{}.improvement_effort;
  std::size_t max_tuples = scenario::CoveringArrayOptions{}.max_tuples;
  std::uint64_t max_search_steps = scenario::kDefaultMaxSearchSteps;
  bool check = false;
};

std::vector<int> parse_levels(const std::string& text) {
  std::vector<int> levels;
  std::size_t start = 0;
  while (true) {
    const auto comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    std::size_t used = 0;
    int value = 0;
    try {
      value = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size())
      throw UsageError(fmt::format("emrm ca: --levels expects comma-separated integers, got '{}'", item));
    if (value < 1) throw UsageError(fmt::format("emrm ca: every level count must be at least 1, got {}", value));
    levels.push_back(value);
    if (comma == text.size()) break;
    start = comma + 1;
  }
  return levels;
}

int run(const CaOptions& o) {
  if (o.model_file.empty() == o.levels.empty())
    throw UsageError("emrm ca: give either a MODEL file or --levels (exactly one)");
  if (o.strength != 2 && o.strength != 3)
    throw UsageError(fmt::format("emrm ca: --strength must be 2 or 3, got {}", o.strength));
  std::optional<scenario::PictModel> model;
  std::vector<int> levels;
  if (!o.model_file.empty()) {
    model.emplace(scenario::load_pict_model(o.model_file, o.max_search_steps));
    levels = model->levels();
  } else {
    levels = parse_levels(o.levels);
  }
  if (static_cast<std::size_t>(o.strength) > levels.size())
    throw UsageError(
        fmt::format("emrm ca: --strength {} needs at least {} factors, got {}", o.strength, o.strength, levels.size()));
  const scenario::RowViolates violates = model ? model->row_violates() : scenario::RowViolates{};
  scenario::CoveringArrayOptions options;
  options.strength = o.strength;
  options.seed = o.seed;
  options.improvement_effort = o.effort;
  options.max_tuples = o.max_tuples;
  options.max_search_steps = o.max_search_steps;
  const auto start = std::chrono::steady_clock::now();
  const scenario::CoveringArray ca = scenario::generate_covering_array(levels, options, violates);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::cout << scenario::covering_array_csv(ca, model ? &*model : nullptr);
  std::cerr << fmt::format("{} rows, strength {}, {} of {} tuples covered ({} excluded by constraints), {:.3f} s\n",
                           ca.rows.size(), ca.strength, ca.required_tuples, ca.required_tuples, ca.forbidden_tuples,
                           seconds);
  if (o.check) {
    const auto report = scenario::check_covering_array(levels, o.strength, ca.rows, violates, o.max_search_steps);
    if (!report.ok()) {
      std::cerr << "check FAILED: " << report.first_problem << "\n";
      return static_cast<int>(ExitCode::kFindings);
    }
    std::cerr << fmt::format("check OK: {} of {} tuples covered, every row valid\n", report.covered_tuples,
                             report.required_tuples);
  }
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_ca_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<CaOptions>();
  auto* cmd = app.add_subcommand("ca",
                                 "Generate a covering array (strength 2 or 3) from level counts or a PICT-style model\n"
                                 "file, printed as CSV; a summary goes to stderr.");
  cmd->add_option("model", o->model_file, "PICT-style model file ('Name: v1, v2' lines and constraints)");
  cmd->add_option("--levels", o->levels, "Comma-separated level counts, e.g. 3,3,3,3 (instead of a model)");
  cmd->add_option("--strength,-t", o->strength, "Interaction strength t, 2 or 3")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Random seed; the same seed gives the same array")
      ->check(seed_value())
      ->capture_default_str();
  cmd->add_option("--effort", o->effort, "Effort of the row-removing search after the greedy array (0: greedy only)")
      ->check(finite_in(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--max-tuples", o->max_tuples, "Most t-tuples to cover (memory grows with them)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1'000'000'000}))
      ->capture_default_str();
  cmd->add_option("--max-search-steps", o->max_search_steps,
                  "Most steps of the constraint search for loading the model, for generating the\n"
                  "array and for --check, each (the search is exponential in the worst case)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1'000'000'000'000}))
      ->capture_default_str();
  cmd->add_flag("--check", o->check, "Verify the array by brute force and print OK (exit 1 if not)");
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace emrm::cli
