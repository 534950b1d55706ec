// Which bare-mesh cleanup step removes the Monte Carlo noise of a CAD mesh: loads MESH with the
// steps given, prints the cleanup counts, the raw view-factor reciprocity asymmetry, the rays
// through one-sided backs and the noise floor (2 seeds). One line per run; not a test.
// Usage: bench_bare_mesh_cleanup MESH STEPS(r=repair,d=duplicates,o=open sheets two-sided,c=coincident; - = none) [rays]
#include <cstdio>
#include <string>

#include "thermodec/nodes/load_model.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/thermal/simulate_model.h"

using namespace thermodec;

int main(int argc, char** argv) {
  const std::string steps = argc > 2 ? argv[2] : "rdoc";
  ModelLoadOptions lo;
  lo.cleanup.repair = steps.find('r') != std::string::npos;
  lo.cleanup.merge_duplicate_faces = steps.find('d') != std::string::npos;
  lo.cleanup.two_sided_open_sheets = steps.find('o') != std::string::npos;
  lo.cleanup.drop_coincident_faces = steps.find('c') != std::string::npos;
  ThermalModel model = load_model(argv[1], lo);
  if (argc > 3) model.radiation.rays_per_face = std::stoi(argv[3]);
  if (model.mesh_cleanup) std::printf("%s", model.mesh_cleanup->summary().c_str());
  const NodeCouplings c = radiative_couplings(model, model.radiation);
  std::printf("asymmetry %.1f sigma, closure %.3g, back hits %lld of %lld rays\n", c.diagnostics.view_factor_asymmetry_sigma,
              c.diagnostics.coupling_closure_error, (long long)c.diagnostics.back_hits_on_one_sided,
              (long long)c.diagnostics.rays_traced);
  const NoiseFloor nf = noise_floor(model, 2);
  std::printf("steps %s: faces %d nodes %zu noise floor %.4f K at %s; %.1f s per simulation\n", steps.c_str(),
              model.mesh.num_faces(), model.nodes.size(), nf.worst.max_abs_K, nf.worst.node.c_str(), nf.run_time_s[0]);
  return 0;
}
