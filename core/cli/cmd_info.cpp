#include "commands.h"

namespace thermodec::cli {

void add_info(CLI::App& app) {
  auto* sub = app.add_subcommand("info", "thermodec info MODEL: mesh and node statistics (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'info'");
}

}  // namespace thermodec::cli
