// thermodec command-line interface: one subcommand per pipeline step.
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "thermodec/common/errors.h"
#include "thermodec/common/interrupt_cleanup.h"
#include "thermodec/common/printable.h"
#include "thermodec/common/release_free_memory.h"
#include "thermodec/common/version.h"
#include "thermodec/thermal/simulation_cost.h"

namespace thermodec::cli {
namespace {
int g_exit_code = 0;
bool g_allow_unknown_keys = false;
int g_max_nodes = thermodec::AutomaticNodeOptions{}.max_nodes;
bool g_force = false;
}

bool force_costly_runs() { return g_force; }

thermodec::ModelLoadOptions model_load_options(const thermodec::MeshReadOptions& mesh, bool clean_bare_mesh) {
  thermodec::ModelLoadOptions o;
  o.mesh = mesh;
  o.clean_bare_mesh = clean_bare_mesh;
  o.allow_unknown_keys = g_allow_unknown_keys;
  o.automatic_nodes.max_nodes = g_max_nodes;
  return o;
}

int exit_code() { return g_exit_code; }
void set_exit_code(int code) { g_exit_code = code; }

void run_guarded(const std::function<void()>& body) {
  // Messages quote file content (names, fields): never raw control bytes on a terminal.
  auto said = [](const std::exception& e) { return printable(e.what(), 4000); };
  try {
    body();
  } catch (const InvalidInput& e) {
    std::cerr << "thermodec: invalid input: " << said(e) << "\n";
    g_exit_code = 1;
  } catch (const IOError& e) {
    std::cerr << "thermodec: I/O error: " << said(e) << "\n";
    g_exit_code = 1;
  } catch (const SolverError& e) {
    std::cerr << "thermodec: solver failed: " << said(e) << "\n";
    g_exit_code = 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "thermodec: out of memory\n";
    g_exit_code = 1;
  } catch (const std::exception& e) {
    std::cerr << "thermodec: error: " << said(e) << "\n";
    g_exit_code = 1;
  }
}

void not_implemented(CLI::App* sub, const std::string& what) {
  sub->callback([what] {
    std::cerr << "thermodec: " << what << " is not implemented yet\n";
    g_exit_code = 2;
  });
}

}  // namespace thermodec::cli

namespace thermodec::cli {
int run_and_exit(CLI::App& app, int argc, char** argv);
}

int main(int argc, char** argv) {
  using namespace thermodec::cli;
  thermodec::remove_temporaries_on_interrupt("thermodec");
  thermodec::keep_freed_memory_for_reuse();  // (one job per process: trials reuse freed blocks)
  CLI::App app{
      "thermodec: simulation-driven mesh reduction for radiative thermal analysis of spacecraft.\n"
      "It splits a model into thermal nodes, measures how sensitive each node is to decimation,\n"
      "reduces each node as far as a temperature tolerance allows, and verifies the result.\n"
      "MODEL is a thermodec model.json (docs/model-format.md) or a bare mesh (.obj .ply .stl,\n"
      "NASTRAN .bdf .nas .dat)."};
  app.require_subcommand(1);
  // Accepted before or after the subcommand (fallthrough).
  app.add_flag("--allow-unknown-keys", g_allow_unknown_keys,
               "Unknown keys in a model file warn instead of failing (e.g. a file from a newer version)");
  app.add_option("--nodes", g_max_nodes,
                 "A mesh without node groups is split into at most N thermal nodes (connected parts, then "
                 "faces of one orientation; the smallest merge first)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  {
    const thermodec::SimulationCostLimits limits;
    char help[400];
    std::snprintf(help, sizeof help,
                  "Run a simulation even when its estimated cost is over the limits: %.0e rays traced, "
                  "%.0e units of thermal solver work (~30 min), %.0f GiB of memory. simulate, viewfactors, export "
                  "and reduce print the estimate and otherwise refuse such a run, naming the setting that "
                  "drives it (docs/model-format.md, \"Validation\")",
                  limits.max_rays, limits.max_solver_work, limits.max_memory_bytes / double(1ull << 30));
    app.add_flag("--force", g_force, help);
  }
  app.fallthrough();
  app.set_version_flag("--version", std::string("thermodec ") + thermodec::kThermodecVersion);
  add_info(app);
  add_convert(app);
  add_nodes(app);
  add_viewfactors(app);
  add_external(app);
  add_simulate(app);
  add_compare(app);
  add_repair(app);
  add_decimate(app);
  add_reduce(app);
  add_export(app);
  add_merge(app);
  // Usage errors follow the same contract as bad input: one line on stderr, exit code 1.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "thermodec: usage error: " + std::string(e.what()) + " (see --help)\n";
  });
  // The first word that is not an option must be a command; CLI11 alone would only say
  // "A subcommand is required".
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') continue;
    std::string names;
    for (const auto* s : app.get_subcommands([](const CLI::App*) { return true; })) {
      if (s->get_name() == word) return run_and_exit(app, argc, argv);
      names += (names.empty() ? "" : ", ") + s->get_name();
    }
    std::cerr << "thermodec: usage error: unknown command '" << word << "' (commands: " << names << "; see --help)\n";
    return 1;
  }
  return run_and_exit(app, argc, argv);
}

namespace thermodec::cli {
int run_and_exit(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;  // --help and --version exit 0
  }
  return exit_code();
}
}  // namespace thermodec::cli
