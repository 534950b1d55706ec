// `thermodec export MODEL --format nastran|esatan|sinda|vtk|csv -o OUT`
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

const char* const kFormatHelp =
    "FORMAT:\n"
    "  nastran  NASTRAN bulk data (.bdf): GRID* (large-field, m), CTRIA3 per face, one PSHELL per thermal\n"
    "           node (name in a '$ thermodec node' comment), RADM alpha/eps per material. For Thermal\n"
    "           Desktop's FE importer, ESA TASverter, Simcenter, FreeCAD FEM. No simulation needed.\n"
    "  esatan   ESATAN-TMS network (.d): $NODES (label, T, C, A, ALP, EPS, QI), $CONDUCTORS GL [W/K] and\n"
    "           GR [m^2], orbit loads per node as cyclic $ARRAYS tables, $EXECUTION SOLVFM (+ SLCRNC).\n"
    "  sinda    SINDA/FLUINT input (.inp): HEADER NODE/CONDUCTOR (radiation conductors with '-' ids)/\n"
    "           ARRAY/CONTROL/VARIABLES 1/OPERATIONS DATA, as Thermal Desktop writes them.\n"
    "  vtk      ParaView series: OUT is a folder; one .vtu per orbit step (cells: node_id, material_id,\n"
    "           area_m2, temperature_K, absorbed_flux_W_per_m2) and MODEL.pvd indexing them by time.\n"
    "  csv      OUT is a prefix: OUT_temperatures.csv (K vs s), OUT_couplings.csv (GL W/K, GR m^2),\n"
    "           OUT_loads.csv (W per node and time).\n"
    "esatan, sinda, vtk and csv simulate MODEL first, exactly as `thermodec simulate` does (same seed,\n"
    "rays and noise-targeted sampling). Units are SI throughout. Details: docs/exchange.md.";

void run_export(const ExportOptions& o) {
  const ExchangeFormat format = exchange_format(o.format);
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
  for (const fs::path& out : export_outputs(format, o.out, fs::path(o.model).stem().string()))
    check_output_file(out, "export: output", format == ExchangeFormat::nastran ? std::vector<std::string>{".bdf", ".nas", ".dat"}
                                                                                : std::vector<std::string>{},
                      {});  // an input in the way: export_model says so, before any work too
  const NoiseTargetingBound noise = settings.noise.target_K > 0.0 && !has_sampling_boosts(model)
                                        ? NoiseTargetingBound{settings.noise.budget, settings.noise.max_samples}
                                        : NoiseTargetingBound{};
  if (format != ExchangeFormat::nastran)
    guard_simulation_cost("export", model, settings.simulation, o.quiet, {}, SimulationCostScope::simulation, noise);
  if (!o.quiet) settings.simulation.progress = [](const std::string& m) { std::cerr << "export: " << m << "\n"; };
  const auto files = export_model(std::move(model), format, o.out, fs::path(o.model).stem().string(), settings);
  if (!o.quiet)
    for (const auto& f : files) std::cerr << "export: wrote " << f.string() << "\n";
}

}  // namespace

void add_export(CLI::App& app) {
  auto opts = std::make_shared<ExportOptions>();
  auto* sub = app.add_subcommand(
      "export",
      "write MODEL (a model or a reduced model) for other tools: NASTRAN bulk data, ESATAN-TMS or "
      "SINDA/FLUINT thermal networks, ParaView VTK series, CSV tables (docs/exchange.md)");
  sub->footer(kFormatHelp);
  sub->add_option("MODEL", opts->model, "model.json or mesh (.obj .ply .stl .bdf)")->required();
  sub->add_option("-f,--format", opts->format, "nastran, esatan, sinda, vtk or csv (see below)")
      ->required()
      ->check(CLI::IsMember({"nastran", "esatan", "sinda", "vtk", "csv"}));
  sub->add_option("-o,--output", opts->out, "output file (vtk: folder; csv: file prefix)")->required();
  sub->add_option("--rays", opts->rays_per_face, "IR view-factor rays per face side (default: the model's)")
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
