#include "commands.h"

namespace thermodec::cli {

void add_simulate(CLI::App& app) {
  auto* sub = app.add_subcommand("simulate", "thermal simulation (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'simulate'");
}

}  // namespace thermodec::cli
