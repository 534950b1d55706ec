#include "commands.h"

namespace thermodec::cli {

void add_external(CLI::App& app) {
  auto* sub = app.add_subcommand("external", "external-geometry extraction (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'external'");
}

}  // namespace thermodec::cli
