// Each node reduced alone (the sensitivity analysis' trial: ratio r for that node, 0 for all
// others): the faces it reaches, how many faces its neighbours lose "for free" on straight
// contours, and the largest relative area change of any other node; then all nodes together. Never a pass/fail. Usage:
//   bench_decimation_node_alone [MODEL.json] [RATIO=0.98]
// Default MODEL: sample_models/satellite/model.json.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include <fmt/core.h>

#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/nodes/load_model.h"

using namespace thermodec;

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : std::string(THERMODEC_SOURCE_DIR) + "/sample_models/satellite/model.json";
  const double ratio = argc > 2 ? std::atof(argv[2]) : 0.98;
  const ThermalModel model = load_model(path);
  const Mesh& mesh = model.mesh;
  const int n = static_cast<int>(mesh.node_names.size());
  fmt::print("{}: {} faces, {} nodes, each node alone at ratio {:.2f}\n", path, mesh.num_faces(), n, ratio);
  fmt::print("{:<20} {:>7} {:>7} {:>7} {:>12} {:>16}\n", "node", "before", "target", "after", "others_free", "others_max_dA");
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
    r[i] = ratio;
    const DecimationResult res = decimate_nodes(mesh, r);
    int free = 0;
    double max_da = 0;
    for (int j = 0; j < static_cast<int>(res.nodes.size()); ++j) {
      if (j == i) continue;
      free += res.nodes[j].faces_before - res.nodes[j].faces_after;
      max_da = std::max(max_da, std::abs(res.nodes[j].relative_area_change()));
    }
    const auto& s = res.nodes[i];
    fmt::print("{:<20} {:>7} {:>7} {:>7} {:>12} {:>16.3e}\n", mesh.node_names[i], s.faces_before, s.target_faces,
               s.faces_after, free, max_da);
  }
  // For comparison: every node at the same ratio in one call.
  const DecimationResult all = decimate_nodes(mesh, Eigen::VectorXd::Constant(n, ratio));
  fmt::print("all nodes together at {:.2f}:", ratio);
  for (int i = 0; i < n; ++i) fmt::print(" {} {}", mesh.node_names[i], all.nodes[i].faces_after);
  fmt::print("\n");
  return 0;
}
