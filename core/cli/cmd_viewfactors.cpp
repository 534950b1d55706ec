#include "commands.h"

namespace thermodec::cli {

void add_viewfactors(CLI::App& app) {
  auto* sub = app.add_subcommand("viewfactors", "node-to-node view factors and radiative couplings (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'viewfactors'");
}

}  // namespace thermodec::cli
