#include "commands.h"

namespace thermodec::cli {

void add_repair(CLI::App& app) {
  auto* sub = app.add_subcommand("repair", "mesh repair (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'repair'");
}

}  // namespace thermodec::cli
