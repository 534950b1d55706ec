#include <chrono>
#include <filesystem>
#include <iostream>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/core.h>

#include "commands.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/face_geometry.h"
#include "thermodec/mesh/io.h"
#include "thermodec/nodes/automatic_nodes.h"
#include "thermodec/nodes/load_model.h"

namespace thermodec::cli {
namespace {

struct NodesArgs {
  std::string model;
  std::string output;
  AutomaticNodeOptions options;
};

void run_nodes(const NodesArgs& args) {
  const std::filesystem::path model_path(args.model);
  std::vector<std::filesystem::path> inputs{model_path};
  Mesh mesh;
  if (model_path.extension() == ".json") {
    // A model file: its mesh in metres (unit_scale applied), with coatings and sidedness.
    ThermalModel model = load_model(model_path, model_load_options());
    inputs.push_back(model.mesh_path);
    mesh = std::move(model.mesh);
  } else {
    mesh = read_mesh(model_path);
  }
  const bool had_groups = !mesh.node_names.empty();

  const auto start = std::chrono::steady_clock::now();
  assign_automatic_nodes(mesh, args.options);
  const double elapsed_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  MeshWriteOptions write_options;
  write_options.protected_inputs = inputs;
  write_mesh(args.output, mesh, write_options);

  const int num_nodes = static_cast<int>(mesh.node_names.size());
  const Eigen::VectorXd area = face_areas(mesh.V, mesh.F);
  const Eigen::MatrixXd normal = face_normals(mesh.V, mesh.F);
  std::vector<int> faces(num_nodes, 0);
  std::vector<double> node_area(num_nodes, 0.0);
  std::vector<Eigen::Vector3d> normal_sum(num_nodes, Eigen::Vector3d::Zero());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int n = mesh.face_node[f];
    ++faces[n];
    node_area[n] += area[f];
    normal_sum[n] += area[f] * normal.row(f).transpose();
  }
  if (had_groups) std::cout << "note: the input's groups were replaced by the automatic breakdown\n";
  std::cout << fmt::format("{}: {} faces -> {} nodes (max angle {} deg, min area fraction {}, "
                           "max nodes {}) in {:.1f} ms\n",
                           args.model, mesh.num_faces(), num_nodes,
                           args.options.max_normal_deviation_deg, args.options.min_node_area_fraction,
                           args.options.max_nodes, elapsed_ms);
  // The mean normal's length says how planar a node is: 1 for a flat panel, less when curved.
  std::cout << fmt::format("{:<10} {:>8} {:>14}  {}\n", "node", "faces", "area [m^2]",
                           "area-weighted mean normal");
  for (int n = 0; n < num_nodes; ++n) {
    const Eigen::Vector3d m = node_area[n] > 0.0 ? Eigen::Vector3d(normal_sum[n] / node_area[n])
                                                 : Eigen::Vector3d::Zero();
    std::cout << fmt::format("{:<10} {:>8} {:>14.6g}  ({:+.3f}, {:+.3f}, {:+.3f})\n",
                             mesh.node_names[n], faces[n], node_area[n], m.x(), m.y(), m.z());
  }
  std::cout << "wrote " << args.output << "\n";
}

}  // namespace

void add_nodes(CLI::App& app) {
  auto args = std::make_shared<NodesArgs>();
  auto* sub = app.add_subcommand(
      "nodes",
      "thermodec nodes MODEL -o OUT: automatic nodal breakdown. Splits the mesh into\n"
      "edge-connected, near-planar regions, merges regions smaller than a share of the total\n"
      "area into the neighbour sharing the longest edge, caps the node count (smallest merged\n"
      "first) and writes the grouped mesh (node_000, node_001, ...). Deterministic.");
  sub->add_option("MODEL", args->model, "model file (.json) or mesh (.obj .ply .stl)")->required();
  sub->add_option("-o,--output", args->output, "grouped mesh to write (.obj .ply .stl)")->required();
  sub->add_option("--max-angle", args->options.max_normal_deviation_deg,
                  "max deviation of a face normal from its region's seed normal [deg]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 180.0));
  sub->add_option("--min-area-fraction", args->options.min_node_area_fraction,
                  "regions below this share of the total area merge into a neighbour")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--max-nodes", args->options.max_nodes, "cap on the number of nodes")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->callback([args] { run_guarded([&] { run_nodes(*args); }); });
}

}  // namespace thermodec::cli
