#include "commands.h"

namespace thermodec::cli {

void add_decimate(CLI::App& app) {
  auto* sub = app.add_subcommand("decimate", "node-preserving decimation (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'decimate'");
}

}  // namespace thermodec::cli
