#pragma once

// Each command registers itself on the top-level app. A command's callback does its work and
// stores its exit code; bad input escapes as emrm::InputError, which main() maps to exit 2.

#include <CLI/CLI.hpp>

namespace emrm::cli {

/// `emrm analyze SAFETY.yaml`: checks a safety case and writes its traceability.
void register_analyze_command(CLI::App& app, int& exit_code);
/// `emrm fsm FSM.yaml`: checks and explores a hazard–loss finite state machine.
void register_fsm_command(CLI::App& app, int& exit_code);
/// `emrm import`: an OpenSCENARIO scenario as a scene, and its trace.
void register_import_command(CLI::App& app, int& exit_code);
/// `emrm families`: the scenario families and their factors.
void register_families_command(CLI::App& app, int& exit_code);
/// `emrm simulate`: one scenario cell under every strategy.
void register_simulate_command(CLI::App& app, int& exit_code);
/// `emrm sweep CAMPAIGN.yaml` and `emrm merge DIR...`: campaigns over the ODD.
void register_sweep_commands(CLI::App& app, int& exit_code);
/// `emrm reproduce -o DIR`: the paper's whole case study.
void register_reproduce_command(CLI::App& app, int& exit_code);
/// `emrm ca`: covering arrays (strength 2 and 3, mixed levels, constraints, PICT models).
void register_ca_command(CLI::App& app, int& exit_code);
/// `emrm plan ODD.yaml -o DIR`: the minimum scenario set.
void register_plan_command(CLI::App& app, int& exit_code);
/// `emrm run SCENARIOS.csv -o DIR`: a planned scenario set through the campaign engine.
void register_run_command(CLI::App& app, int& exit_code);
/// `emrm report DIR`: figures and report.html from a results folder.
void register_report_command(CLI::App& app, int& exit_code);
/// `emrm verify DIR`: re-checks a results store without trusting it.
void register_verify_command(CLI::App& app, int& exit_code);
/// `emrm diagnose DIR`: the campaign diagnostics on any results store.
void register_diagnose_command(CLI::App& app, int& exit_code);
/// `emrm boundary DIR`: the TTC boundaries of each region and strategy, as CSV and figures.
void register_boundary_command(CLI::App& app, int& exit_code);
/// `emrm export`: a cell or a plan as OpenSCENARIO XML and OpenDRIVE.
void register_export_command(CLI::App& app, int& exit_code);
/// `emrm assess TRAJECTORIES.csv`: a recorded trajectory judged by emrm's models.
void register_assess_command(CLI::App& app, int& exit_code);
/// `emrm calibrate`: fits the brakes' actuation to measured brake tests.
void register_calibrate_command(CLI::App& app, int& exit_code);

}  // namespace emrm::cli
