#include <filesystem>
#include <fmt/format.h>
#include <iostream>

#include "commands.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/load_model.h"

namespace thermodec::cli {
namespace {

struct ConvertArgs {
  std::string input;
  std::string output;
  bool ascii = false;
  bool drop_degenerate = false;
  double weld_tolerance = MeshReadOptions{}.weld_tolerance;
};

void run_convert(const ConvertArgs& args) {
  const std::filesystem::path in(args.input), out(args.output);
  if (same_file(in, out)) throw InvalidInput("refusing to overwrite the input " + args.input + ": choose another OUT");
  MeshReadOptions read;
  read.weld_tolerance = args.weld_tolerance;
  read.drop_degenerate_faces = args.drop_degenerate;
  MeshWriteOptions write;
  write.binary = !args.ascii;
  write.protected_inputs = {in};
  Mesh mesh;
  std::string ext = in.extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".json") {
    // A model: write its mesh with every face's node and resolved material.
    ThermalModel model = load_model(in, model_load_options(read, false));
    write.protected_inputs.push_back(model.mesh_path);
    mesh = std::move(model.mesh);
  } else {
    mesh = read_mesh(in, read);
  }
  write_mesh(out, mesh, write);
  std::cout << fmt::format("{} -> {}: {} faces, {} vertices, {} nodes, {} materials\n", args.input, args.output,
                           mesh.num_faces(), mesh.num_vertices(), mesh.node_names.size(), mesh.material_names.size());
  std::string out_ext = out.extension().string();
  for (auto& c : out_ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (out_ext == ".stl" && (!mesh.node_names.empty() || !mesh.material_names.empty()))
    std::cout << (args.ascii ? "note: STL keeps node names as solids but no materials or sidedness\n"
                             : "note: binary STL keeps geometry only: nodes, materials and sidedness are not stored\n");
}

}  // namespace

void add_convert(CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  auto* sub = app.add_subcommand(
      "convert",
      "Convert a mesh between OBJ, PLY and STL (format from each file's extension), keeping node\n"
      "groups, materials and two-sidedness where the output format can hold them. IN may also be a\n"
      "model file (.json): its mesh is written with the model's nodes and resolved materials.\n"
      "OUT is written atomically and never overwrites IN.");
  sub->add_option("IN", args->input, "input mesh (.obj .ply .stl) or model file (.json)")->required();
  sub->add_option("OUT", args->output, "output mesh (.obj .ply .stl)")->required();
  sub->add_flag("--ascii", args->ascii, "write ascii PLY/STL instead of binary");
  sub->add_flag("--drop-degenerate", args->drop_degenerate, "drop zero-area faces (listed on stderr)");
  sub->add_option("--weld-tolerance", args->weld_tolerance,
                  "merge vertices closer than this [IN file units]; < 0 disables (STL: exact duplicates)")
      ->capture_default_str();
  sub->callback([args] { run_guarded([&] { run_convert(*args); }); });
}

}  // namespace thermodec::cli
