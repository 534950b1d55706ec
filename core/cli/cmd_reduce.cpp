#include "commands.h"

namespace thermodec::cli {

void add_reduce(CLI::App& app) {
  auto* sub = app.add_subcommand("reduce", "simulation-driven reduction (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'reduce'");
}

}  // namespace thermodec::cli
