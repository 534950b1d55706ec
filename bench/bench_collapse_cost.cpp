// Collapse cost benchmark: the geometric (Lindstrom-Turk) and the radiative ranking of the
// decimator's collapses at equal budgets. One line per model, ratio and cost: faces after,
// the largest change of a node's projected area over 200 directions relative to its area (what
// the Sun, the planet and distant surfaces see of it), the median over nodes, and CPU time.
// Never a pass/fail. Usage:
//   bench_collapse_cost [MODEL ...]   (default: the sample and the NASA meshes in ../shared)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <sys/resource.h>

#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/mesh/mesh_stats.h"
#include "thermodec/nodes/load_model.h"
#include "projected_areas.h"

namespace fs = std::filesystem;
using namespace thermodec;
using bench::cpu_seconds;
using bench::projected_areas;

int main(int argc, char** argv) {
  std::vector<fs::path> models;
  for (int i = 1; i < argc; ++i) models.emplace_back(argv[i]);
  if (models.empty()) {
    const fs::path src = THERMODEC_SOURCE_DIR;
    models = {src / "sample_models/satellite/model.json"};
    for (const char* m : {"NPP_16.stl", "Juno.stl", "tdrs.stl"})
      if (fs::exists(src / "../shared/models/nasa" / m)) models.push_back(src / "../shared/models/nasa" / m);
  }
  std::printf("%-12s %5s %-10s %7s %7s %12s %12s %8s\n", "model", "ratio", "cost", "faces", "after", "max dP/A",
              "median dP/A", "cpu s");
  for (const auto& path : models) {
    const ThermalModel model = load_model(path);
    const Mesh& mesh = model.mesh;
    const int nodes = static_cast<int>(model.nodes.size());
    const auto p0 = projected_areas(mesh, nodes, 200);
    const std::vector<double> area = node_areas_m2(mesh);  // [m^2], one entry per node
    for (const double ratio : {0.5, 0.8})
      for (const auto kind : {CollapseCostKind::geometric, CollapseCostKind::radiative}) {
        DecimationOptions o;
        o.collapse_cost = kind;
        o.max_relative_area_change = 7.5e-4;  // reduce's bound at 0.5 K on the NASA meshes
        const double t0 = cpu_seconds();
        const DecimationResult r = decimate_nodes(mesh, Eigen::VectorXd::Constant(nodes, ratio), o);
        const double t = cpu_seconds() - t0;
        const auto p1 = projected_areas(r.mesh, nodes, 200);
        std::vector<double> change(nodes, 0.0);
        for (int n = 0; n < nodes; ++n)
          for (size_t k = 0; k < p0[n].size(); ++k)
            if (area[n] > 0) change[n] = std::max(change[n], std::abs(p1[n][k] - p0[n][k]) / area[n]);
        std::vector<double> sorted = change;
        std::sort(sorted.begin(), sorted.end());
        std::printf("%-12s %5.2f %-10s %7d %7d %12.3e %12.3e %8.3f\n", path.stem().string().c_str(), ratio,
                    kind == CollapseCostKind::geometric ? "geometric" : "radiative", mesh.num_faces(),
                    r.mesh.num_faces(), sorted.back(), sorted[sorted.size() / 2], t);
      }
  }
  return 0;
}
