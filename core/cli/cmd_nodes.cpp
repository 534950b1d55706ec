#include "commands.h"

namespace thermodec::cli {

void add_nodes(CLI::App& app) {
  auto* sub = app.add_subcommand("nodes", "automatic nodal breakdown (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'nodes'");
}

}  // namespace thermodec::cli
