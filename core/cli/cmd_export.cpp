// `thermodec export MODEL --format nastran|esatan|sinda|vtk|csv -o OUT`
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/exchange/exported_network.h"
#include "thermodec/exchange/write_csv_tables.h"
#include "thermodec/exchange/write_esatan_network.h"
#include "thermodec/exchange/write_nastran_bulk.h"
#include "thermodec/exchange/write_sinda_network.h"
#include "thermodec/exchange/write_vtk_series.h"
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
  // The same noise-targeted sampling as `simulate` (its defaults), so that the exported
  // couplings and loads are the ones `simulate` solves.
  double noise_target_K = 0.0025;
  double noise_budget = 32.0;
  double noise_max_samples = 2e8;
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

// Checks the output before any expensive work: never onto an input, never a folder where a
// file goes (or the reverse).
void check_output(const ExportOptions& o, const std::vector<fs::path>& inputs) {
  if (o.out.empty()) throw InvalidInput("export: -o OUT is empty");
  std::vector<fs::path> outs{o.out};
  if (o.format == "csv") {
    const std::string prefix = fs::path(o.out).extension() == ".csv" ? fs::path(o.out).replace_extension().string() : o.out;
    outs = {prefix + "_temperatures.csv", prefix + "_couplings.csv", prefix + "_loads.csv"};
  }
  std::error_code ec;
  for (const auto& out : outs) {
    for (const auto& in : inputs)
      if (same_file(in, out)) throw InvalidInput("export: output " + out.string() + " would overwrite the input " + in.string());
    const bool folder = fs::is_directory(out, ec);
    if (o.format == "vtk" && fs::exists(out, ec) && !folder)
      throw InvalidInput("export vtk: " + out.string() + " is a file; OUT must be a folder (created if missing)");
    if (o.format != "vtk" && folder) throw InvalidInput("export " + o.format + ": " + out.string() + " is a folder, not a file");
    const fs::path parent = fs::absolute(out).parent_path();
    if (!parent.empty() && fs::exists(parent, ec) && !fs::is_directory(parent, ec))
      throw InvalidInput("export: " + parent.string() + " is not a folder");
  }
}

void run_export(const ExportOptions& o) {
  ModelLoadOptions load;
  load.clean_bare_mesh = !o.raw_mesh;
  ThermalModel model = load_model(o.model, load);
  const std::vector<fs::path> inputs{o.model, model.mesh_path};
  check_output(o, inputs);
  auto say = [&](const std::string& m) {
    if (!o.quiet) std::cerr << "export: " << m << "\n";
  };
  if (o.format == "nastran") {
    write_nastran_bulk(o.out, model, inputs);
    say("wrote " + o.out + " (" + std::to_string(model.mesh.num_vertices()) + " GRID, " +
        std::to_string(model.mesh.num_faces()) + " CTRIA3, " + std::to_string(model.nodes.size()) + " nodes)");
    return;
  }
  ModelSimulationSettings settings;
  if (!o.raw_mesh) apply_bare_mesh_ray_budgets(model, settings);
  if (o.rays_per_face > 0) model.radiation.rays_per_face = o.rays_per_face;
  if (!o.quiet) settings.progress = [](const std::string& m) { std::cerr << "export: simulate: " << m << "\n"; };
  if (o.noise_target_K > 0.0 && !has_sampling_boosts(model)) {
    say("sampling: estimating each node's Monte Carlo noise");
    const SamplingBoosts b = decide_sampling_boosts(model, settings, o.noise_target_K, o.noise_budget, o.noise_max_samples);
    for (std::size_t k = 0; k < b.boost.size(); ++k) model.nodes[k].sampling_boost = b.boost[k];
    say(b.describe(model.nodes));
  }
  NodeCouplings couplings;
  const SimulationResult result = simulate_model(model, settings, &couplings);
  const ExportedNetwork network = exported_network(model, couplings, result, o.model);
  if (o.format == "esatan") {
    write_esatan_network(o.out, network, inputs);
    say("wrote " + o.out);
  } else if (o.format == "sinda") {
    write_sinda_network(o.out, network, inputs);
    say("wrote " + o.out);
  } else if (o.format == "vtk") {
    const fs::path pvd = write_vtk_series(o.out, fs::path(o.model).stem().string(), model, network, inputs);
    say("wrote " + pvd.string() + " and " + std::to_string(network.times_s.size()) + " .vtu steps");
  } else {
    const fs::path out(o.out);
    const fs::path prefix = out.extension() == ".csv" ? fs::path(out).replace_extension() : out;
    for (const auto& p : write_csv_tables(prefix, network, inputs)) say("wrote " + p.string());
  }
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
