#include "commands.h"

namespace thermodec::cli {

void add_convert(CLI::App& app) {
  auto* sub = app.add_subcommand("convert", "convert a mesh between OBJ, PLY and STL (not implemented yet)");
  sub->allow_extras();
  not_implemented(sub, "'convert'");
}

}  // namespace thermodec::cli
