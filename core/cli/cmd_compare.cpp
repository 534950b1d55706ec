#include "commands.h"

namespace thermodec::cli {

void add_compare(CLI::App& app) {
  auto* sub = app.add_subcommand("compare", "compare two simulation results (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'compare'");
}

}  // namespace thermodec::cli
