// External loads on the sample satellite: full run vs a trial with one node changed reusing a
// reference run's samples (environment/external_loads.h LoadReuse), one line per node.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <string>

#include "thermodec/environment/external_loads.h"
#include "thermodec/nodes/load_model.h"

using namespace thermodec;
using Clock = std::chrono::steady_clock;
static double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : std::string(THERMODEC_SOURCE_DIR) + "/sample_models/satellite/model.json";
  const ThermalModel model = load_model(path);
  const ExternalLoadSettings settings;
  LoadSamples reference;
  auto t0 = Clock::now();
  {
    const RayScene scene(model.mesh);
    external_loads(model, scene, surface_sides(model), nullptr, settings, {}, &reference);
  }
  std::size_t record_bytes = reference.earth_records.bytes();
  for (const auto& r : reference.sun_records) record_bytes += r.bytes();
  std::printf("%s: reference loads %.3f s (%d faces), per-ray records %s, %.1f MB\n", path.c_str(), since(t0),
              model.mesh.num_faces(), reference.per_ray ? "kept" : "NOT kept", record_bytes / 1e6);
  {  // full runs without recording, best of 3
    const RayScene scene(model.mesh);
    const SurfaceSides sides = surface_sides(model);
    double best = 1e30, best_cpu = 1e30;
    for (int i = 0; i < 3; ++i) {
      t0 = Clock::now();
      const std::clock_t c0 = std::clock();
      external_loads(model, scene, sides, nullptr, settings);
      best_cpu = std::min(best_cpu, double(std::clock() - c0) / CLOCKS_PER_SEC);
      best = std::min(best, since(t0));
    }
    std::printf("full loads (no recording, no reflections): best of 3 %.3f s wall, %.3f s CPU (all threads)\n", best,
                best_cpu);
  }
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    // Trial: the node's free vertices pulled 10 % towards the centroid of its shared ones.
    std::vector<int> uses(model.mesh.num_vertices(), 0), mine(model.mesh.num_vertices(), 0);
    for (int f = 0; f < model.mesh.num_faces(); ++f)
      for (int c = 0; c < 3; ++c) ++uses[model.mesh.F(f, c)], mine[model.mesh.F(f, c)] += model.mesh.face_node[f] == int(n);
    Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
    int k = 0;
    for (int v = 0; v < model.mesh.num_vertices(); ++v)
      if (mine[v] && mine[v] < uses[v]) pivot += model.mesh.V.row(v).transpose(), ++k;
    if (k == 0) continue;
    pivot /= k;
    ThermalModel trial = model;
    Eigen::AlignedBox3d changed;
    for (int v = 0; v < model.mesh.num_vertices(); ++v)
      if (mine[v]) {
        changed.extend(Eigen::Vector3d(model.mesh.V.row(v).transpose()));
        if (mine[v] == uses[v]) trial.mesh.V.row(v) = (pivot + 0.9 * (model.mesh.V.row(v).transpose() - pivot)).transpose();
        changed.extend(Eigen::Vector3d(trial.mesh.V.row(v).transpose()));
      }
    const RayScene scene(trial.mesh);
    const SurfaceSides sides = surface_sides(trial);
    t0 = Clock::now();
    const Loads full = external_loads(trial, scene, sides, nullptr, settings);
    const double t_full = since(t0);
    LoadReuse reuse{&reference, changed};
    t0 = Clock::now();
    const Loads inc = external_loads(trial, scene, sides, nullptr, settings, {}, nullptr, &reuse);
    const double t_inc = since(t0);
    const bool same = inc.total_W() == full.total_W();
    std::printf("%-12s full %.3f s, reusing %.3f s => %.1fx (whole sides reused: shadows %.0f %%, Earth views %.0f %%; "
                "then rays reused: sun %.0f %% of %ld, Earth %.0f %% of %ld)%s\n",
                model.nodes[n].name.c_str(), t_full, t_inc, t_full / t_inc, 100.0 * reuse.reused_sun / reuse.total_sun,
                100.0 * reuse.reused_earth / reuse.total_earth,
                100.0 * reuse.reused_sun_rays / std::max(1L, reuse.reused_sun_rays + reuse.traced_sun_rays),
                reuse.reused_sun_rays + reuse.traced_sun_rays,
                100.0 * reuse.reused_earth_rays / std::max(1L, reuse.reused_earth_rays + reuse.traced_earth_rays),
                reuse.reused_earth_rays + reuse.traced_earth_rays, same ? "" : "  RESULTS DIFFER");
  }
  return 0;
}
