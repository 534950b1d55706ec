// Decimation reach benchmark: every node asked for ratio 0.9 under reduce's decimation options
// (reduction_decimation_options) and reduce's area bound at 0.5 K on the NASA meshes (7.5e-4),
// decimate_nodes directly. One line per model: faces after, the refused edges of the nodes left
// above their target by the first check that refuses them (NodeDecimationStats::blocked_edges,
// in brackets the nodes each reason stops most), the largest and median change of a node's
// projected area over 200 directions relative to its area, and CPU time. Never a pass/fail.
// Usage:
//   bench_decimation_reach [--normal DEG] [--contour D] [--budget B] [--fold DEG] [--kink D] [--wide-kink F] [--wide-kink-part F] [--area A]
//                          [--node-areas REPORT.json] [--geometric] [--conforming] [--passes N] [--ratio R]
//                          [--cap F] [--fixed-areas] [--per-node] [MODEL ...]
//   --cap F: DecimationOptions::projected_area_cap (0 = off); --fixed-areas: restore_node_areas off
//   --conforming: contacts not released (DecimationOptions::release_contacts off); --passes N:
//   DecimationOptions::passes
//   --ratio R: every node asked for R instead of 0.9; --per-node: one more line per node (faces
//   before -> after, target, its largest projected-area change over 200 directions and its area
//   change, both relative to its area, and its refused edges by reason)
//   (--node-areas: the per-node area bounds `reduce` used, its report's
//   "node_max_relative_area_change", for the one MODEL it reduced)
//   (default: the NASA meshes in ../shared; options override reduce's decimation options)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/mesh/mesh_stats.h"
#include "thermodec/nodes/load_model.h"
#include "projected_areas.h"
#include "thermodec/reduction/reduction_reference.h"

namespace fs = std::filesystem;
using namespace thermodec;
using bench::cpu_seconds;
using bench::projected_areas;

int main(int argc, char** argv) {
  DecimationOptions o = reduction_decimation_options();
  o.max_relative_area_change = 7.5e-4;  // reduce's bound at 0.5 K on the NASA meshes
  std::vector<fs::path> models;
  double ratio = 0.9;
  bool per_node = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&] { return i + 1 < argc ? std::atof(argv[++i]) : 0.0; };
    if (a == "--normal") o.max_normal_deviation_deg = value();
    else if (a == "--contour") o.max_contour_deviation = value();
    else if (a == "--budget") o.projected_area_budget = value();
    else if (a == "--kink") o.max_kinked_contour_deviation = value();
    else if (a == "--wide-kink") o.wide_kink_area_fraction = value();
    else if (a == "--wide-kink-part") o.wide_kink_part_fraction = value();
    else if (a == "--fold") o.max_fold_deg = value();
    else if (a == "--area") o.max_relative_area_change = value();
    else if (a == "--geometric") o.collapse_cost = CollapseCostKind::geometric;
    else if (a == "--ratio") ratio = value();
    else if (a == "--per-node") per_node = true;
    else if (a == "--conforming") o.release_contacts = false;
    else if (a == "--passes") o.passes = static_cast<int>(value());
    else if (a == "--cap") o.projected_area_cap = value();
    else if (a == "--fixed-areas") o.restore_node_areas = false;
    else if (a == "--node-areas" && i + 1 < argc) {
      std::ifstream in(argv[++i]);
      const nlohmann::json report = nlohmann::json::parse(in);
      o.node_max_relative_area_change = report.at("node_max_relative_area_change").get<std::vector<double>>();
    }
    else models.emplace_back(a);
  }
  if (models.empty()) {
    const fs::path src = THERMODEC_SOURCE_DIR;
    for (const char* m : {"NPP_16.stl", "Juno.stl"})
      if (fs::exists(src / "../shared/models/nasa" / m)) models.push_back(src / "../shared/models/nasa" / m);
  }
  std::printf("# cost %s, normals %g deg, contour %g, projected-area budget %g (fold %g deg, kink %g), area %g%s, %d pass(es), "
              "projected-area cap %g%s\n",
              o.collapse_cost == CollapseCostKind::geometric ? "geometric" : "radiative", o.max_normal_deviation_deg,
              o.max_contour_deviation, o.projected_area_budget, o.max_fold_deg, o.max_kinked_contour_deviation,
              o.max_relative_area_change, o.release_contacts ? ", contacts released" : "", o.passes,
              o.projected_area_cap, o.projected_area_cap > 0 && o.restore_node_areas ? ", areas restored" : "");
  if (!o.node_max_relative_area_change.empty()) {
    auto b = o.node_max_relative_area_change;
    std::sort(b.begin(), b.end());
    std::printf("# per-node area bounds (%zu): min %.3g, median %.3g, max %.3g\n", b.size(), b.front(), b[b.size() / 2],
                b.back());
  }
  for (const auto& path : models) {
    const ThermalModel model = load_model(path);
    const Mesh& mesh = model.mesh;
    const int nodes = static_cast<int>(model.nodes.size());
    const auto p0 = projected_areas(mesh, nodes, 200);
    const std::vector<double> area = node_areas_m2(mesh);  // [m^2], one entry per node
    const double t0 = cpu_seconds();
    const DecimationResult r = decimate_nodes(mesh, Eigen::VectorXd::Constant(nodes, ratio), o);
    const double t = cpu_seconds() - t0;
    const auto p1 = projected_areas(r.mesh, nodes, 200);
    std::vector<double> change(nodes, 0.0);
    for (int n = 0; n < nodes; ++n)
      for (size_t k = 0; k < p0[n].size(); ++k)
        if (area[n] > 0) change[n] = std::max(change[n], std::abs(p1[n][k] - p0[n][k]) / area[n]);
    const std::vector<double> node_change = change;
    std::sort(change.begin(), change.end());
    std::array<int, kCollapseBlocks> edges{}, stopped{};
    for (const auto& s : r.nodes) {
      for (int k = 0; k < kCollapseBlocks; ++k) edges[k] += s.blocked_edges[k];
      if (!s.reached) ++stopped[static_cast<int>(s.stopped_by())];
    }
    std::string why;
    std::vector<int> order(kCollapseBlocks);
    for (int k = 0; k < kCollapseBlocks; ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return edges[a] > edges[b]; });
    for (int k : order)
      if (edges[k] > 0)
        why += std::string(why.empty() ? "" : ", ") + collapse_block_name(static_cast<CollapseBlock>(k)) + " " +
               std::to_string(edges[k]) + (stopped[k] > 0 ? " (" + std::to_string(stopped[k]) + ")" : "");
    std::printf("%-8s %6d -> %6d (%.1f %%)  max dP/A %.2e, median %.2e  %.2f s  %s\n", path.stem().string().c_str(),
                mesh.num_faces(), r.mesh.num_faces(), 100.0 * r.mesh.num_faces() / mesh.num_faces(), change.back(),
                change[change.size() / 2], t, why.c_str());
    if (per_node)
      for (int n = 0; n < nodes && n < static_cast<int>(r.nodes.size()); ++n) {
        const NodeDecimationStats& s = r.nodes[n];
        std::string blocks;
        for (int k = 0; k < kCollapseBlocks; ++k)
          if (s.blocked_edges[k] > 0)
            blocks += std::string(" ") + collapse_block_name(static_cast<CollapseBlock>(k)) + " " +
                      std::to_string(s.blocked_edges[k]);
        std::printf("  %-16s %5d -> %5d (target %d, free %d, dP/A %.1e, dA/A %+.1e)%s\n", model.nodes[n].name.c_str(),
                    s.faces_before, s.faces_after, s.target_faces, s.faces_removed_free, node_change[n],
                    s.area_before_m2 > 0 ? s.area_after_m2 / s.area_before_m2 - 1 : 0.0, blocks.c_str());
      }
  }
  return 0;
}
