// thermodec external MODEL -o OUT: keep the faces visible from outside the spacecraft.
#include <fmt/core.h>

#include <chrono>

#include "commands.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/radiation/external_geometry.h"

namespace thermodec::cli {
namespace {

struct ExternalOptions {
  std::string model;
  std::string out;
  int rays = 256;
  long long seed = 1;
  bool both_sides = false;
};

void run(const ExternalOptions& o) {
  ThermalModel model = load_model(o.model, model_load_options());
  const std::filesystem::path out(o.out);
  for (const auto& input : {std::filesystem::path(o.model), model.mesh_path})
    if (!input.empty() && same_file(out, input))
      throw InvalidInput("output " + o.out + " is an input; choose another path (inputs are never overwritten)");
  ExternalSettings settings;
  settings.rays_per_face = o.rays;
  settings.seed = static_cast<std::uint64_t>(o.seed);
  settings.both_sides = o.both_sides;
  const auto t0 = std::chrono::steady_clock::now();
  const RayScene scene(model.mesh);
  const ExternalFaces ext = external_faces(scene, settings);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Mesh kept = extract_external(model.mesh, ext);

  fmt::print("{:<20} {:>8} {:>8}\n", "node", "kept", "dropped");
  for (int i = 0; i < ext.kept_per_node.size(); ++i) {
    const bool unassigned = i == ext.kept_per_node.size() - 1;
    if (unassigned && ext.kept_per_node[i] + ext.dropped_per_node[i] == 0) continue;
    fmt::print("{:<20} {:>8} {:>8}\n", unassigned ? "(no node)" : model.mesh.node_names[i], ext.kept_per_node[i],
               ext.dropped_per_node[i]);
  }
  fmt::print("{} of {} faces external ({} dropped, {} of them zero-area); {} rays in {:.2f} s\n", ext.kept,
             model.mesh.num_faces(), ext.dropped, ext.untraceable, ext.rays_traced, seconds);
  if (kept.num_faces() == 0) fmt::print("warning: no face is visible from outside (inward-facing mesh? try --both-sides)\n");

  if (out.extension() == ".json") {
    std::filesystem::path mesh_path = out;
    mesh_path.replace_extension(".obj");
    for (const auto& input : {std::filesystem::path(o.model), model.mesh_path})
      if (!input.empty() && same_file(mesh_path, input))
        throw InvalidInput("output mesh " + mesh_path.string() + " would overwrite an input");
    model.mesh = std::move(kept);
    model.certificate.reset();  // a changed mesh no longer is the verified one
    save_model(model, out, mesh_path);
    fmt::print("wrote {} and {}\n", out.string(), mesh_path.string());
  } else {
    write_mesh(out, kept);
    fmt::print("wrote {}\n", out.string());
  }
}

}  // namespace

void add_external(CLI::App& app) {
  auto opts = std::make_shared<ExternalOptions>();
  auto* sub = app.add_subcommand(
      "external",
      "thermodec external MODEL -o OUT: keep only the faces visible from outside (rays escaping to infinity); "
      "OUT is a mesh (.obj .ply .stl) or a model .json (mesh written beside it as .obj)");
  sub->add_option("MODEL", opts->model, "model.json or mesh (.obj .ply .stl)")->required();
  sub->add_option("-o,--output", opts->out, "output mesh or model.json")->required();
  sub->add_option("--rays,--rays-per-face", opts->rays, "visibility rays per face side, at most (default 256)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--seed", opts->seed, "random seed (default 1)")->check(CLI::NonNegativeNumber);
  sub->add_flag("--both-sides", opts->both_sides, "also test the back of one-sided faces (unreliable orientation)");
  sub->callback([opts] { run_guarded([&] { run(*opts); }); });
}

}  // namespace thermodec::cli
