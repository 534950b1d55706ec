#include <filesystem>
#include <iostream>

#include <fmt/core.h>

#include "commands.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"
#include "thermodec/mesh/repair.h"
#include "thermodec/nodes/load_model.h"

namespace thermodec::cli {
namespace {

namespace fs = std::filesystem;

struct RepairArgs {
  std::string model;
  std::string output;
  RepairOptions options;
  bool old_tolerance_option = false;  // --tolerance, the deprecated name of --weld-fraction
};

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

// OUT.json -> model + OUT.obj beside it; OUT.obj/.ply -> mesh + OUT.json; OUT.stl -> mesh only.
void write_model_or_mesh(const ThermalModel& model, const fs::path& out, const fs::path& input) {
  const std::string ext = out.extension().string();
  fs::path json = out, mesh = out;
  if (ext == ".json")
    mesh.replace_extension(".obj");
  else
    json.replace_extension(".json");
  for (const fs::path& p : {json, mesh})
    if (same_file(p, input) || (!model.mesh_path.empty() && same_file(p, model.mesh_path)))
      throw InvalidInput(p.string() + ": refusing to overwrite an input file");
  if (ext == ".stl") {
    MeshWriteOptions w;
    w.protected_inputs = {input, model.mesh_path};
    write_mesh(out, model.mesh, w);
    std::cout << "wrote " << out.string() << " (STL keeps geometry only; no model written)\n";
    return;
  }
  ThermalModel repaired = model;
  repaired.certificate.reset();  // a changed mesh no longer is the verified one
  save_model(repaired, json, mesh);
  std::cout << "wrote " << json.string() << " and " << mesh.string() << "\n";
}

void run_repair(const RepairArgs& args) {
  if (args.old_tolerance_option)
    std::cerr << "repair: warning: --tolerance is deprecated, use --weld-fraction (a fraction of the bounding-box "
                 "diagonal; --tolerance means kelvin in reduce and compare)\n";
  MeshReadOptions read;
  read.drop_degenerate_faces = false;  // repair drops them and says so
  ThermalModel model = load_model(args.model, model_load_options(read, false));
  const int faces_before = model.mesh.num_faces(), vertices_before = model.mesh.num_vertices();
  RepairResult r = repair_mesh(model.mesh, args.options);
  model.mesh = std::move(r.mesh);
  std::cout << fmt::format("{}: {} faces, {} vertices -> {} faces, {} vertices\n", args.model, faces_before,
                           vertices_before, model.mesh.num_faces(), model.mesh.num_vertices());
  std::cout << r.report.summary();
  write_model_or_mesh(model, args.output, args.model);
}

}  // namespace

void add_repair(CLI::App& app) {
  auto args = std::make_shared<RepairArgs>();
  auto* sub = app.add_subcommand(
      "repair",
      "thermodec repair MODEL -o OUT: welds coincident vertices, drops degenerate and duplicate\n"
      "faces, splits faces at T-junctions (recursive edge bisection) so the mesh is conforming,\n"
      "orients faces consistently (closed parts outward) and reports non-manifold edges and\n"
      "vertices, which are kept. Prints what it changed. OUT.json writes the model and OUT.obj;\n"
      "OUT.obj/.ply writes the mesh and OUT.json; OUT.stl writes geometry only.");
  sub->add_option("MODEL", args->model, "model file (.json) or mesh (.obj .ply .stl)")->required();
  sub->add_option("-o,--output", args->output, "output model (.json) or mesh (.obj .ply .stl)")->required();
  auto* weld = sub->add_option("--weld-fraction", args->options.relative_tolerance,
                               "weld / T-junction distance as a fraction of the bounding-box diagonal")
                   ->capture_default_str()
                   ->check(CLI::NonNegativeNumber);
  // The old name, kept so that scripts run on with a warning: elsewhere --tolerance is kelvin
  // (reduce, compare) and --weld-tolerance a length (info, convert). Hidden from the help.
  sub->add_option_function<double>(
         "--tolerance",
         [args](double f) {
           args->options.relative_tolerance = f;
           args->old_tolerance_option = true;
         },
         "deprecated: --weld-fraction")
      ->check(CLI::NonNegativeNumber)
      ->excludes(weld)
      ->group("");
  sub->add_flag("!--no-orient", args->options.orient, "keep face orientations as they are");
  sub->add_flag("!--no-conform", args->options.conform_t_junctions, "do not split T-junctions");
  sub->callback([args] { run_guarded([&] { run_repair(*args); }); });
}

}  // namespace thermodec::cli
