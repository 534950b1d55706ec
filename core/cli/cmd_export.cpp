// `thermodec export MODEL --format FORMAT -o OUT`, FORMAT a row of exchange/export_formats.h.
#include <algorithm>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "thermodec/common/output_paths.h"
#include "thermodec/exchange/export_model.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec::cli {
namespace {

namespace fs = std::filesystem;

struct ExportOptions {
  std::string model;
  std::string format;
  std::string out;
  int rays_per_face = 0;  // 0 = the model's
  bool raw_mesh = false;
  bool quiet = false;
  double noise_target_K = NoiseTargeting{}.target_K;  // as `simulate`
};

// The FORMAT section of the help, one entry per row of the core's table.
std::string format_help() {
  std::string text = "FORMAT:\n";
  for (const ExportFormat& f : export_formats()) {
    std::string name = "  " + f.name;
    name.resize(std::max<size_t>(name.size() + 1, 11), ' ');
    std::string indent(name.size(), ' ');
    std::string help = f.help;
    for (size_t at = help.find('\n'); at != std::string::npos; at = help.find('\n', at + 1 + indent.size()))
      help.insert(at + 1, indent);
    text += name + help + "\n";
  }
  std::string simulated;
  for (const ExportFormat& f : export_formats())
    if (f.needs_simulation) simulated += (simulated.empty() ? "" : ", ") + f.name;
  return text + simulated +
         " simulate MODEL first, exactly as `thermodec simulate` does (same seed, rays and\n"
         "noise-targeted sampling). Units are SI throughout. Details: docs/exchange.md.";
}

void run_export(const ExportOptions& o) {
  const ExportFormat& format = export_format(o.format);
  ModelLoadOptions load = model_load_options();
  load.clean_bare_mesh = !o.raw_mesh;
  ThermalModel model = load_model(o.model, load);
  ExportSettings settings;
  settings.protected_inputs = {o.model, model.mesh_path};
  settings.title = o.model;
  settings.noise.target_K = o.noise_target_K;
  if (!o.raw_mesh) apply_bare_mesh_ray_budgets(model, settings.simulation);
  if (o.rays_per_face > 0) model.radiation.rays_per_face = o.rays_per_face;
  // The outputs are checked before the cost estimate and the simulation (export_model checks
  // them again): a kind, extension or folder that cannot take them is said at once.
  check_export_outputs(format, o.out, fs::path(o.model).stem().string(), settings.protected_inputs);
  if (format.needs_simulation)
    guard_simulation_cost("export", check_front_end_simulation_cost(model, settings.simulation, settings.noise), o.quiet);
  if (!o.quiet) settings.simulation.progress = [](const std::string& m) { std::cerr << "export: " << m << "\n"; };
  const auto files = export_model(std::move(model), format.name, o.out, fs::path(o.model).stem().string(), settings);
  if (!o.quiet)
    for (const auto& f : files) std::cerr << "export: wrote " << f.string() << "\n";
}

}  // namespace

void add_export(CLI::App& app) {
  auto opts = std::make_shared<ExportOptions>();
  std::string titles;
  for (const ExportFormat& f : export_formats()) titles += (titles.empty() ? "" : ", ") + f.title;
  auto* sub = app.add_subcommand(
      "export", "write MODEL (a model or a reduced model) for other tools: " + titles + " (docs/exchange.md)");
  sub->footer(format_help());
  sub->add_option("MODEL", opts->model, "model.json or mesh (.obj .ply .stl .bdf)")->required();
  sub->add_option("-f,--format", opts->format, export_format_choices() + " (see below)")
      ->required()
      ->check(CLI::IsMember(export_format_names()));
  sub->add_option("-o,--output", opts->out, "output: a file, a folder or a file prefix, as the format says (below)")->required();
  sub->add_option("--rays,--rays-per-face", opts->rays_per_face, "IR view-factor rays per face side (default: the model's)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--noise-target", opts->noise_target_K,
                  "noise-targeted sampling as in `simulate` [K] (0 = off)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e3));
  sub->add_flag("--raw-mesh", opts->raw_mesh, "bare mesh: skip the cleanup and the size-aware ray budgets");
  sub->add_flag("-q,--quiet", opts->quiet, "no progress output");
  sub->callback([opts] { run_guarded([opts] { run_export(*opts); }); });
}

}  // namespace thermodec::cli
