// Direct sun with self-shadowing.
//
// Computes, per face side and time step, the incident direct solar power S A max(0, n . s) x
// (the fraction of the side's sample points that see the sun past the spacecraft itself) [W],
// zero in eclipse; the side's absorptivity makes it absorbed power (external_loads.cpp). The
// sample points are the first N points of the side's Owen-scrambled Sobol net (load_sides.h);
// a pilot of P of them decides fully lit or fully shadowed sides, a conservative sphere test
// (occluders.h) sides nothing can shadow. Accuracy: a shadow edge is a smooth curve on the face,
// so the lit fraction's error is ~sqrt(p (1 - p)) N^-3/4 (Owen's rate for such indicators),
// which is what the loads' error estimate adds.
#include "direct_sun.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "load_run.h"
#include "shadow_controls.h"

namespace thermodec::load_rays {
namespace {

// Which sides facing `toward` (unit) may be shadowed at all: some potential blocker's bounding
// sphere meets the prism their rays sweep (the side's bounding sphere moved along `toward`).
// The others are lit whatever their sample points, exactly, and need no rays. Only the sides
// flagged in `todo` (all if null) are tested: a trial reuses the others whole (for the sample's
// 60 sun directions per trial, testing every side cost ~2 % of an incremental trial).
std::vector<char> may_be_shadowed(const std::vector<Side>& geo, const Occluders& occ, const Eigen::Vector3d& toward,
                                  const std::vector<char>* todo = nullptr) {
  const int ns = static_cast<int>(geo.size());
  std::vector<char> out(ns, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 64), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s < range.end(); ++s) {
      const double facing = geo[s].normal.dot(toward);
      if (occ.radius[s] < 0.0 || facing <= 0.0 || (todo && !(*todo)[s])) continue;
      if (facing < 1e-6) {  // grazing: float rays could sink below the lift, let Embree decide
        out[s] = 1;
        continue;
      }
      // a blocker's sphere meets the prism the side's sphere sweeps along `toward`
      out[s] = any_blocker(geo, occ, s, [&](const Eigen::Vector3d& centre, double reach) {
        const Eigen::Vector3d v = centre - occ.centre[s];
        const double along = v.dot(toward);
        if (along < -reach) return false;  // wholly behind the rays' start
        return v.squaredNorm() - along * along <= reach * reach;
      });
    }
  });
  return out;
}

// Points from..to of a side traced along d in groups by the set of hulls their rays cross
// (shadow_controls.h): adds each set's points to n[mask] and its open ones to open[mask];
// returns how many are open.
int count_open_by_mask(SideTracer& tracer, const std::vector<std::array<float, 3>>& points, int from, int to,
                       const float* d, const SideStrata& strata, const std::vector<NodeHull>& hulls,
                       std::vector<double>& n, std::vector<double>& open) {
  std::vector<std::vector<std::array<float, 3>>> by_mask(n.size());
  for (int k = from; k < to; ++k) by_mask[stratum_of_ray(strata, hulls, points[k].data(), d)].push_back(points[k]);
  int total = 0;
  for (std::size_t m = 0; m < by_mask.size(); ++m) {
    if (by_mask[m].empty()) continue;
    const int o = tracer.count_open(by_mask[m].data(), 0, static_cast<int>(by_mask[m].size()), d);
    n[m] += static_cast<double>(by_mask[m].size());
    open[m] += o;
    total += o;
  }
  return total;
}

}  // namespace

Eigen::VectorXd sunlit_fraction(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                                const Eigen::Vector3d& toward, const Eigen::VectorXi& side_rays, int pilot_rays,
                                std::uint64_t seed, const tracing::SobolTable& sobol, const Occluders& occ,
                                const PassContext& pass, std::vector<std::vector<std::array<float, 3>>>& origins,
                                const std::vector<char>* todo, const std::vector<NodeHull>* controls) {
  const int ns = sides.size();
  Eigen::VectorXd frac = Eigen::VectorXd::Zero(ns);
  const float dir[3] = {float(toward.x()), float(toward.y()), float(toward.z())};
  const bool recording = pass.recording();
  const std::vector<char> shadowable = may_be_shadowed(geo, occ, toward, todo);
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 32), [&](const tbb::blocked_range<int>& range) {
    SideTracer tracer(scene, recording, pass.change);
    SideRays rays_out;
    for (int s = range.begin(); s < range.end(); ++s) {
      const Side& g = geo[s];
      if (g.area <= 0.0 || g.normal.dot(toward) <= 0.0 || (todo && !(*todo)[s])) continue;
      if (!shadowable[s]) {  // exact: every sample point sees the sun
        frac[s] = 1.0;
        continue;
      }
      const int rays = side_rays[s], pilot = pilot_count(rays, pilot_rays);
      tracer.begin(&rays_out, pass.cursor(s));
      // Traces sample points from..to of the side's scrambled net; returns how many see the sun.
      auto trace = [&](const std::array<std::uint32_t, 4>& sd, int from, int to) {
        const std::size_t first = rays_out.blocked.size();
        auto& points = origins[s];  // (a side is one thread's at a step, and steps run in turn)
        for (int k = static_cast<int>(points.size()); k < to; ++k)
          on_side(g, scrambled(sobol[k][0], sd[0]), scrambled(sobol[k][1], sd[1]), points.emplace_back().data());
        if (!recording) return tracer.count_open(points.data(), from, to, dir);  // (outcomes not kept)
        for (int k = from; k < to; ++k) tracer.add(points[k].data(), dir);
        tracer.flush();
        int open = 0;
        for (std::size_t i = first; i < rays_out.blocked.size(); ++i) open += !rays_out.blocked[i];
        return open;
      };
      const auto sd = side_seeds(seed, sides.key[s], 1);
      // Shadow control variates (a pass that keeps no records): the side's points counted by
      // the set of hulls their rays cross, the lit fraction post-stratified by those sets.
      const SideStrata strata = controls && !recording && !pass.ref_records
                                    ? shadow_strata(g, sides.node[s], toward, *controls)
                                    : SideStrata{};
      std::vector<double> n(std::size_t(1) << strata.count, 0.0), open(n.size(), 0.0);
      const auto count = [&](int from, int to) {
        if (strata.count == 0) return trace(sd, from, to);
        trace(sd, to, to);  // draws the points up to `to` (traces none)
        return count_open_by_mask(tracer, origins[s], from, to, dir, strata, *controls, n, open);
      };
      const int open_pilot = count(0, pilot);
      if (open_pilot == 0 || open_pilot == pilot || (pilot == rays && strata.count == 0)) {
        frac[s] = double(open_pilot) / pilot;
      } else if (strata.count > 0) {
        if (pilot < rays) count(pilot, rays);
        const std::vector<double> w = stratum_weights(strata, n);
        double lit = 0.0;
        for (std::size_t m = 0; m < n.size(); ++m) lit += w[m] * open[m];
        frac[s] = std::clamp(lit, 0.0, 1.0);
      } else {
        frac[s] = double(open_pilot + trace(sd, pilot, rays)) / rays;
      }
      if (recording) pass.recorder->keep(*pass.record, s, rays_out);
    }
    pass.count(tracer);
  });
  return frac;
}

void direct_sun_loads(LoadRun& run) {
  const auto& progress = run.progress;
  const int steps = run.steps, ns = run.ns, num_nodes = run.num_nodes;
  const std::vector<OrbitState>& states = run.states;
  Loads& loads = run.loads;
  const double flux = run.flux;
  const LoadSamples* ref = run.ref;
  LoadReuse* reuse = run.reuse;
  LoadSamples* samples = run.samples;
  const std::vector<Side>& geo = run.geo;
  const SurfaceSides& sides = run.sides;
  const Eigen::VectorXi& sun_rays = run.sun_rays_per_pass;
  const Eigen::VectorXd& alpha = run.alpha;
  const std::vector<int>& ref_of = run.ref_of;
  Eigen::MatrixXd& incident_direct = run.incident_direct;
  // One shadow computation per distinct sun direction in body axes (a single one
  // for sun-pointing and inertial attitudes or a fixed sun): the passes sun_passes() counts.
  if (progress) progress("direct sun: " + std::to_string(steps) + " step(s)");
  Eigen::Vector3d last_dir = Eigen::Vector3d::Zero();
  Eigen::VectorXd lit;
  // Sample points per side: the same at every pass, or (own_shadow_points: a steady orbit's
  // passes, sun_rays_per_pass of them, or a transient orbit's, all of them; external_loads.h)
  // each pass's own, from its own scramble seed.
  std::vector<std::vector<std::array<float, 3>>> sun_points(ns);
  const bool own_points = run.own_shadow_points;
  std::vector<char> todo(ns, 1);
  for (int k = 0; k < steps; ++k) {
    const OrbitState& st = states[k];
    loads.in_shadow[k] = st.in_shadow;
    if (st.in_shadow || flux == 0.0) continue;
    if (lit.size() == 0 || !same_direction(st.sun_direction_body, last_dir)) {
      int reused_here = 0;
      if (ref) {
        // (each side's test alone: in parallel, the same flags)
        tbb::parallel_for(tbb::blocked_range<int>(0, ns, 256), [&](const tbb::blocked_range<int>& range) {
          for (int s = range.begin(); s < range.end(); ++s)
            todo[s] = !(run.same_counts(s) && run.reach->clear_along(s, st.sun_direction_body));
        });
        for (int s = 0; s < ns; ++s) reused_here += !todo[s];
      }
      if (reuse) {
        reuse->reused_sun += reused_here;
        reuse->total_sun += ns;
      }
      if (own_points)
        for (auto& p : sun_points) p.clear();
      const std::uint64_t pass_seed =
          own_points ? sampling::hash_combine(run.settings.seed, 0x5a55ull + std::uint64_t(k)) : run.settings.seed;
      const PassContext pass =
          run.make_pass(ref && static_cast<int>(ref->sun_records.size()) == steps ? &ref->sun_records[k] : nullptr,
                        &run.reused_sun_rays, &run.traced_sun_rays);
      lit = sunlit_fraction(run.scene, geo, sides, st.sun_direction_body, sun_rays, run.settings.sun_pilot_rays,
                            pass_seed, run.sobol(), run.occ, pass, sun_points, ref ? &todo : nullptr,
                            ref || run.shadow_hulls.empty() ? nullptr : &run.shadow_hulls);
      if (pass.recording() && run.recorder.active()) samples->sun_records[k] = run.take_records();
      if (ref)
        for (int s = 0; s < ns; ++s)
          if (!todo[s]) lit[s] = ref->sunlit(ref_of[s], k);
      last_dir = st.sun_direction_body;
    }
    if (samples) samples->sunlit.col(k) = lit;
    for (int s = 0; s < ns; ++s) {
      const double full = flux * geo[s].area * std::max(0.0, geo[s].normal.dot(st.sun_direction_body));
      incident_direct(s, k) = full * lit[s];
      // Shadow-sample error of a partly lit side (lit share p of N scrambled-net points): a
      // shadow edge is a smooth curve on the face, which cuts ~sqrt(N) of the net's N strata,
      // each an error of at most 1/N: sigma_p ~ sqrt(p (1 - p)) N^-3/4 (Owen's N^-3/4 for
      // such indicators), not the binomial sqrt(p (1 - p) / N), which overstated the measured
      // seed-to-seed differences ~16x (docs/thermal.md). Variances are summed per node here
      // and combined with the Earth rays' by the driver (external_loads.cpp).
      const int node = sides.node[s];
      if (lit[s] > 0.0 && lit[s] < 1.0 && node >= 0 && node < num_nodes && sun_rays[s] > 0)
        run.sun_variance(node, k) +=
            std::pow(alpha[s] * full * std::sqrt(lit[s] * (1.0 - lit[s])) * std::pow(double(sun_rays[s]), -0.75), 2);
    }
  }
}

}  // namespace thermodec::load_rays
