// Where the Monte Carlo noise of an orbit simulation comes from, and what it costs.
// For seeds 1 and 2 it swaps one stage's seed at a time (IR view factors / couplings, sun
// shadow samples, Earth rays) and prints the max |dT| each causes, with stage timings.
// Usage: bench_thermal_noise [MODEL] [rays_per_face] [sun_rays] [earth_rays] [earth_min_rays_per_node]
//        [min_rays_per_node] [sun_min_rays_per_node]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "thermodec/environment/external_loads.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/radiation/gebhart_factors.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/thermal/network.h"
#include "thermodec/thermal/simulate.h"
#include "thermodec/thermal/temperature_noise.h"

using namespace thermodec;
using Clock = std::chrono::steady_clock;
static double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : std::string(THERMODEC_SOURCE_DIR) + "/sample_models/satellite/model.json";
  ThermalModel model = load_model(path);
  if (argc > 2) model.radiation.rays_per_face = std::stoi(argv[2]);
  ExternalLoadSettings ls;
  if (argc > 3) ls.sun_rays_per_face = std::stoi(argv[3]);
  if (argc > 4) ls.earth_rays_per_face = std::stoi(argv[4]);
  if (argc > 5) ls.earth_min_rays_per_node = std::stoi(argv[5]);
  if (argc > 6) model.radiation.min_rays_per_node = std::stoi(argv[6]);
  if (argc > 7) ls.sun_min_rays_per_node = std::stoi(argv[7]);
  // BENCH_BOOST="dish=4,boom=8/2": Node::sampling_boost per node, both or IR/loads (experiments).
  if (const char* b = std::getenv("BENCH_BOOST")) {
    std::string spec = b;
    for (std::size_t at = 0; at < spec.size();) {
      const std::size_t end = std::min(spec.find(',', at), spec.size()), eq = spec.find('=', at);
      for (Node& n : model.nodes)
        if (eq < end && n.name == spec.substr(at, eq - at)) {
          const std::string v = spec.substr(eq + 1, end - eq - 1);  // "4" (both) or "8/2" (IR/loads)
          const std::size_t slash = v.find('/');
          n.sampling_boost.ir = std::stod(v.substr(0, slash));
          n.sampling_boost.loads = slash == std::string::npos ? n.sampling_boost.ir : std::stod(v.substr(slash + 1));
        }
      at = end + 1;
    }
  }
  const int N = static_cast<int>(model.nodes.size());
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  const Eigen::VectorXd eps = side_emissivity(model, sides);

  struct Stage { FaceViewFactors vf; NodeCouplings nc; };
  auto couple = [&](std::uint64_t seed, double* t_vf, double* t_gb) {
    RadiationSettings rs = model.radiation;
    rs.seed = seed;
    auto t0 = Clock::now();
    Stage s;
    s.vf = face_view_factors(scene, sides, rs);
    *t_vf = since(t0);
    t0 = Clock::now();
    const GebhartFactors gb = gebhart_factors(s.vf, eps, node_groups(sides, N), N + 1);
    s.nc = aggregate_couplings(s.vf, eps, gb, N);
    *t_gb = since(t0);
    return s;
  };
  // Second seed: BENCH_SEED2 (default 2); the first is 1.
  const std::uint64_t s2 = std::getenv("BENCH_SEED2") ? std::stoull(std::getenv("BENCH_SEED2")) : 2;
  // First seed: BENCH_SEED1 (default 1; the loads' seeds mix sun and Earth, see below).
  const std::uint64_t s1 = std::getenv("BENCH_SEED1") ? std::stoull(std::getenv("BENCH_SEED1")) : 1;
  double t_vf, t_gb;
  const Stage a = couple(s1, &t_vf, &t_gb), b = couple(s2, &t_vf, &t_gb);
  auto loads = [&](const FaceViewFactors& vf, std::uint64_t sun_seed, std::uint64_t earth_seed, double* t) {
    ExternalLoadSettings s = ls;
    // Different seeds for sun and Earth sampling: combine them into one (only for this bench).
    s.seed = sun_seed * 1000003ull + earth_seed;
    auto t0 = Clock::now();
    Loads l = external_loads(model, scene, sides, &vf, s);
    *t = since(t0);
    return l;
  };
  double t_loads;
  const Loads la = loads(a.vf, s1, s1, &t_loads);
  const Loads lb = loads(a.vf, s2, s2, &t_loads);
  const Loads lvf = loads(b.vf, s1, s1, &t_loads);
  auto t0 = Clock::now();
  const SimulationResult ra = simulate(model, a.nc, la);
  const double t_solve = since(t0);
  const SimulationResult rb_ir = simulate(model, b.nc, la);
  const auto d_couplings = compare_results(ra, rb_ir);
  const auto d_loads = compare_results(ra, simulate(model, a.nc, lb));
  const auto d_reflect = compare_results(ra, simulate(model, a.nc, lvf));
  const auto d_all = compare_results(ra, simulate(model, b.nc, lvf.period_s ? loads(b.vf, s2, s2, &t_loads) : lb));
  std::printf("%s: %d faces, %d sides, %d nodes, rays/face %d, sun rays %d, earth rays %d\n", path.c_str(),
              model.mesh.num_faces(), sides.size(), N, model.radiation.rays_per_face, ls.sun_rays_per_face,
              ls.earth_rays_per_face);
  std::printf("timing: view factors %.3f s, Gebhart+aggregate %.3f s, loads %.3f s, solve %.3f s\n", t_vf, t_gb,
              t_loads, t_solve);
  std::printf("max |dT| seed 1 vs 2: IR couplings only %.4f K (%s); sun+Earth sampling only %.4f K (%s); "
              "solar-reflection view factors only %.4f K (%s); everything %.4f K (%s)\n",
              d_couplings.max_abs_K, d_couplings.node.c_str(), d_loads.max_abs_K, d_loads.node.c_str(),
              d_reflect.max_abs_K, d_reflect.node.c_str(), d_all.max_abs_K, d_all.node.c_str());
  {  // which load of the sampling stage: swap one load family from seed 2 into seed 1
    Loads ls_sun = la, ls_earth = la;
    ls_sun.solar_W = lb.solar_W;
    ls_earth.albedo_W = lb.albedo_W;
    ls_earth.earth_ir_W = lb.earth_ir_W;
    const auto d_sun = compare_results(ra, simulate(model, a.nc, ls_sun));
    const auto d_earth = compare_results(ra, simulate(model, a.nc, ls_earth));
    std::printf("  of which direct sun (shadow samples) %.4f K (%s), albedo + Earth IR %.4f K (%s)\n", d_sun.max_abs_K,
                d_sun.node.c_str(), d_earth.max_abs_K, d_earth.node.c_str());
  }
  const Eigen::MatrixXd dl = (la.total_W() - lb.total_W()).cwiseAbs();
  Eigen::Index i, k;
  dl.maxCoeff(&i, &k);
  std::printf("largest load difference (sampling): %.4f W at %s step %d (solar %.3f, albedo %.3f, IR %.3f)\n",
              dl(i, k), model.nodes[i].name.c_str(), int(k), std::abs(la.solar_W(i, k) - lb.solar_W(i, k)),
              std::abs(la.albedo_W(i, k) - lb.albedo_W(i, k)), std::abs(la.earth_ir_W(i, k) - lb.earth_ir_W(i, k)));
  const ThermalNetwork net = thermal_network(model, a.nc);
  const Eigen::VectorXd sigma_ir = temperature_standard_error_K(net, a.nc, ra.temperature_K);
  const Eigen::VectorXd sigma_loads = temperature_standard_error_from_loads_K(
      net, ra.temperature_K, ra.transient ? la.sampling_standard_error_W : Eigen::MatrixXd(la.sampling_standard_error_W.rowwise().mean()));
  std::printf("orbit-mean load differences per node [W] (sampling seed 1 vs 2): solar / albedo / IR / reflected, of total;"
              " then the estimated temperature standard errors (couplings, loads) and max |dT| (IR only) [K]\n");
  for (int n = 0; n < N; ++n)
    std::printf("  %-12s %8.4f %8.4f %8.4f %8.4f  of %8.2f   %8.4f %8.4f %8.4f\n", model.nodes[n].name.c_str(),
                (la.solar_W - lb.solar_W).row(n).mean(), (la.albedo_W - lb.albedo_W).row(n).mean(),
                (la.earth_ir_W - lb.earth_ir_W).row(n).mean(), (la.reflected_solar_W - lb.reflected_solar_W).row(n).mean(),
                la.total_W().row(n).mean(), sigma_ir[n], sigma_loads[n], (ra.temperature_K - rb_ir.temperature_K).row(n).cwiseAbs().maxCoeff());
  return 0;
}
