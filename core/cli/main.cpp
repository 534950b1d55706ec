// thermodec command-line interface: one subcommand per pipeline step.
#include <iostream>

#include "commands.h"
#include "thermodec/common/errors.h"

namespace thermodec::cli {
namespace {
int g_exit_code = 0;
}

int exit_code() { return g_exit_code; }

void run_guarded(const std::function<void()>& body) {
  try {
    body();
  } catch (const InvalidInput& e) {
    std::cerr << "thermodec: invalid input: " << e.what() << "\n";
    g_exit_code = 1;
  } catch (const IOError& e) {
    std::cerr << "thermodec: I/O error: " << e.what() << "\n";
    g_exit_code = 1;
  } catch (const SolverError& e) {
    std::cerr << "thermodec: solver failed: " << e.what() << "\n";
    g_exit_code = 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "thermodec: out of memory\n";
    g_exit_code = 1;
  } catch (const std::exception& e) {
    std::cerr << "thermodec: error: " << e.what() << "\n";
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

int main(int argc, char** argv) {
  using namespace thermodec::cli;
  CLI::App app{
      "thermodec: simulation-driven mesh reduction for radiative thermal analysis of spacecraft.\n"
      "It splits a model into thermal nodes, measures how sensitive each node is to decimation,\n"
      "reduces each node as far as a temperature tolerance allows, and verifies the result.\n"
      "MODEL is a thermodec model.json (docs/model-format.md) or a bare mesh (.obj .ply .stl,\n"
      "NASTRAN .bdf .nas .dat)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "thermodec 0.1.0");
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
  // Usage errors follow the same contract as bad input: one line on stderr, exit code 1.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "thermodec: usage error: " + std::string(e.what()) + " (see --help)\n";
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;  // --help and --version exit 0
  }
  return exit_code();
}
