#pragma once
// Each subcommand lives in its own file cmd_<name>.cpp and only parses options into the
// core's option structs, calls the core and prints; no algorithm lives in the CLI.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "thermodec/nodes/load_case.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/thermal/simulation_cost.h"

namespace thermodec::cli {

void add_info(CLI::App& app);
void add_convert(CLI::App& app);
void add_nodes(CLI::App& app);
void add_viewfactors(CLI::App& app);
void add_external(CLI::App& app);
void add_simulate(CLI::App& app);
void add_compare(CLI::App& app);
void add_repair(CLI::App& app);
void add_decimate(CLI::App& app);
void add_reduce(CLI::App& app);
void add_export(CLI::App& app);
void add_merge(CLI::App& app);

//! Runs `body`, mapping thermodec errors to a one-line message on stderr and exit code 1.
//! Sets the process exit code through `exit_code`.
void run_guarded(const std::function<void()>& body);

//! For subcommands whose capability has not landed yet: says so, exits non-zero.
void not_implemented(CLI::App* sub, const std::string& what);

int exit_code();

//! The model's environment and analysis as {"environment": {...}, "analysis": {...}}, with the
//! model file's own keys (nodes/model_sections.h): they paste back into a model file.
nlohmann::ordered_json environment_analysis_json(const thermodec::ThermalModel& model);
//! The same as two aligned lines for text output.
std::string environment_analysis_text(const thermodec::ThermalModel& model);
//! Sets the process exit code (e.g. 3 for `compare --tolerance` exceeded).
void set_exit_code(int code);

//! Model loading options carrying the global `--allow-unknown-keys` flag; `mesh` and
//! `clean_bare_mesh` as given (load_model(path, MeshReadOptions) takes meshes as read).
thermodec::ModelLoadOptions model_load_options(const thermodec::MeshReadOptions& mesh = {}, bool clean_bare_mesh = true);

//! The global `--force` flag: run even when a simulation's estimated cost is over the limits.
bool force_costly_runs();

//! Noise-targeted sampling's bound on extra samples (thermal/simulate_model.h,
//! decide_sampling_boosts): max_extra x the model's total of a kind, at most max_samples; 0 = off.
//! Before the expensive work of `command`: prints the core's estimate (check_simulation_cost,
//! thermal/simulation_cost.h: one simulation, and one per load case, with noise-targeted
//! sampling's extras where they apply) on stderr unless `quiet`, and refuses a run over
//! SimulationCostLimits or the machine's memory with InvalidInput naming the setting that drives
//! it, unless `--force` was given (then a warning).
void guard_simulation_cost(const std::string& command, const thermodec::SimulationCostCheck& check, bool quiet);

}  // namespace thermodec::cli
