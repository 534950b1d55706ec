// Where a node's reflected sunlight comes from: for MODEL and a target node, the orbit-mean
// solar-band power the target absorbs after diffuse reflections, split by the node whose faces
// reflected it first, and its single-bounce part at face level (sunlit side s reflects
// (1 - alpha_s) of its incident power, the target absorbs alpha_t of what lands on it:
// F(s, t) from the side-level view factors). Run on a reference and a decimated model with the
// same node names to see which nodes' decimation moves the target's reflected load, and
// whether through the node-level view (the same fraction of its reflected power) or through
// which of its faces are lit (the same faces seeing the target differently).
//   [SOURCE_NODE=name] bench_reflection_sources MODEL NODE [MODEL2]   (SOURCE_NODE: its sides)
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/gebhart_factors.h"
#include "thermodec/radiation/reciprocal_view_factors.h"
#include "thermodec/thermal/simulate_model.h"

using namespace thermodec;

namespace {

struct Source {
  double incident_W = 0;   // orbit-mean solar-band power incident on the node's sides
  double reflected_W = 0;  // what the target absorbs of it after any number of reflections
  double single_W = 0;     // the same, first bounce only
};

std::map<std::string, Source> sources(const std::string& path, const std::string& target) {
  ThermalModel model = load_model(path);
  ModelSimulationSettings settings;
  apply_bare_mesh_ray_budgets(model, settings);
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  const FaceViewFactors vf = face_view_factors(scene, sides, model.radiation);
  Eigen::MatrixXd incident;
  ExternalLoadSettings ls = chain_load_settings(model, settings);
  const Loads loads = external_loads(model, scene, sides, &vf, ls, {}, nullptr, nullptr, &incident);
  const Eigen::Index steps = loads.reflected_solar_W.cols();  // orbit positions; knots after them
  const Eigen::VectorXd alpha = side_absorptivity(model, sides);
  const int G = static_cast<int>(model.nodes.size());
  int t = -1;
  for (int g = 0; g < G; ++g)
    if (model.nodes[g].name == target) t = g;
  if (t < 0) throw InvalidInput("no node " + target);
  const FaceViewFactors rec = reciprocal_view_factors(vf);
  const GebhartFactors B = gebhart_factors(rec, alpha, node_groups(sides, G), G + 1);
  std::map<std::string, Source> out;
  const Eigen::VectorXd mean_in = incident.leftCols(steps).rowwise().mean();
  std::printf("%s: %s absorbs %.2f W of reflected sunlight (the loads' own figure), %.2f W direct\n", path.c_str(),
              target.c_str(), loads.reflected_solar_W.row(t).mean(), loads.solar_W.row(t).mean());
  const char* detail = std::getenv("SOURCE_NODE");  // print this node's sides
  for (int s = 0; s < sides.size(); ++s) {
    if (sides.node[s] < 0) continue;
    Source& src = out[model.nodes[sides.node[s]].name];
    double to_target = 0;  // F(s, target's sides)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rec.F, s); it; ++it)
      if (sides.node[it.col()] == t) to_target += it.value();
    if (detail && model.nodes[sides.node[s]].name == detail) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero(), nrm;
      const int f = sides.face[s];
      for (int k = 0; k < 3; ++k) c += model.mesh.V.row(model.mesh.F(f, k)).transpose() / 3.0;
      const Eigen::Vector3d a = model.mesh.V.row(model.mesh.F(f, 0)).transpose(), b = model.mesh.V.row(model.mesh.F(f, 1)).transpose(),
                            d = model.mesh.V.row(model.mesh.F(f, 2)).transpose();
      nrm = (b - a).cross(d - a).normalized() * (sides.is_back[s] ? -1.0 : 1.0);
      std::printf("  side %5d face %5d back %d area %9.3f m2 flux %8.2f W/m2 F_to_target %.4f reflected_to_target %8.2f W "
                  "centre (%.2f %.2f %.2f) normal (%.2f %.2f %.2f)\n",
                  s, f, sides.is_back[s], sides.area_m2[s], mean_in[s] / sides.area_m2[s], to_target,
                  (1 - alpha[s]) * B.B(s, t) * mean_in[s], c[0], c[1], c[2], nrm[0], nrm[1], nrm[2]);
    }
    src.incident_W += mean_in[s];
    src.reflected_W += (1 - alpha[s]) * B.B(s, t) * mean_in[s];
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rec.F, s); it; ++it)
      if (sides.node[it.col()] == t) src.single_W += (1 - alpha[s]) * it.value() * alpha[it.col()] * mean_in[s];
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_reflection_sources MODEL NODE [MODEL2]\n");
    return 2;
  }
  const auto a = sources(argv[1], argv[2]);
  std::map<std::string, Source> b;
  if (argc > 3) b = sources(argv[3], argv[2]);
  double ta = 0, tb = 0, sa = 0, sb = 0;
  std::printf("%-10s %12s %12s %12s %12s %12s %12s\n", "source", "incident_W", "reflected_W", "single_W",
              "incident2_W", "reflected2_W", "single2_W");
  for (const auto& [name, s] : a) {
    const Source o = b.count(name) ? b.at(name) : Source{};
    ta += s.reflected_W, tb += o.reflected_W, sa += s.single_W, sb += o.single_W;
    std::printf("%-10s %12.2f %12.3f %12.3f %12.2f %12.3f %12.3f\n", name.c_str(), s.incident_W, s.reflected_W,
                s.single_W, o.incident_W, o.reflected_W, o.single_W);
  }
  std::printf("total reflected into %s: %.2f W (single bounce %.2f W); second model %.2f W (%.2f W)\n", argv[2], ta, sa,
              tb, sb);
  return 0;
}
