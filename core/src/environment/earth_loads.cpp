// Earth IR and albedo, with the share of the Earth the spacecraft itself blocks.
//
// Computes, per node and time step, the absorbed Earth IR eps q_IR A F_side->Earth and the
// absorbed albedo alpha a S A sum over the side's unblocked Earth rays of w max(0, n_E . s)
// [W] (a diffuse Lambertian Earth lit by the sun, so the terminator and the lit crescent seen
// from eclipse are resolved). The rays: for an Earth fixed in body axes (nadir), cone rays once
// (earth_cone.h, ratio estimator, exact for unobstructed sides); else escaping hemisphere rays
// once, intersected with the Earth's cone at every step (escaping_rays.h). Accuracy: the
// binomial error of the blocked share, added to the loads' error estimate for cone rays.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "earth_cone.h"
#include "escaping_rays.h"
#include "load_run.h"
#include "thermodec/common/errors.h"

namespace thermodec::load_rays {
namespace {

// The Earth rays of one run: view factors and kept rays per side, and which sides reuse the
// reference's lighting sums.
struct EarthSampling {
  double distance = 0.0;   // orbit radius [m]
  bool earth_fixed = true;  // the Earth keeps its direction in body axes
  std::vector<char> earth_todo;  // per side: traced again (not reused whole)
  std::vector<char> replayed;    // per side: traced again, every ray kept its reference outcome
  bool ref_lit = false;          // the reference's per-step lighting sums are usable
  EarthHits hits;                // Earth fixed in body axes
  EscapingRays escaping;         // else
  // Side s's per-step lighting sums are the reference's (the same rays, the same sums).
  bool sums_from_reference(int s) const { return ref_lit && (!earth_todo[s] || replayed[s]); }
};

EarthSampling sample_earth(LoadRun& run) {
  const Environment& env = run.model.environment;
  const auto& progress = run.progress;
  const int steps = run.steps, ns = run.ns;
  const std::vector<OrbitState>& states = run.states;
  const LoadSamples* ref = run.ref;
  LoadReuse* reuse = run.reuse;
  LoadSamples* samples = run.samples;
  const RayScene& scene = run.scene;
  const SurfaceSides& sides = run.sides;
  const ExternalLoadSettings& settings = run.settings;
  const std::vector<Side>& geo = run.geo;
  const Occluders& occ = run.occ;
  const tracing::SobolTable& sobol = run.sobol();
  const std::vector<int>& ref_of = run.ref_of;
  const Eigen::VectorXi& earth_rays = run.earth_rays;
  EarthSampling e;
  if (progress) progress("Earth view factors");
  e.distance = orbit_radius_m(env);
  const double distance = e.distance;
  bool& earth_fixed = e.earth_fixed;
  earth_fixed = earth_fixed_in_body(states);
  if (ref && ref->earth_fixed != earth_fixed)
    throw InvalidInput("external loads: reference samples are for another attitude");
  const double radius = env.body_radius_m;
  const double half_angle = std::asin(radius / distance);
  std::vector<char>& earth_todo = e.earth_todo;
  earth_todo.assign(ns, 1);
  std::vector<char> may_be_blocked;
  if (earth_fixed) {
    // For every side (not only those traced): a side reused whole must also have taken the
    // same pilot decision, which depends on this conservative test as well as on its rays.
    may_be_blocked = may_be_blocked_from_earth(geo, occ, states[0].earth_direction_body.normalized(),
                                               radius / distance, nullptr);
    if (samples) samples->earth_may_be_blocked = may_be_blocked;
  }
  const bool ref_has_decisions = ref && static_cast<int>(ref->earth_may_be_blocked.size()) == static_cast<int>(ref->key.size());
  if (ref)
    for (int s = 0; s < ns; ++s) {
      // note: a side that no face can block, here and in the reference, has all its rays open
      // in both (never traced, the same pilot decision): reused whole wherever the change is.
      earth_todo[s] = !(run.same_counts(s) &&
                        (earth_fixed ? ref_has_decisions && may_be_blocked[s] == ref->earth_may_be_blocked[ref_of[s]] &&
                                           (!may_be_blocked[s] ||
                                            run.reach->clear_in_cone(s, states[0].earth_direction_body.normalized(), half_angle))
                                     : run.reach->clear_in_front(s)));
      reuse->reused_earth += !earth_todo[s];
      reuse->total_earth += 1;
    }
  EarthHits& hits = e.hits;
  EscapingRays& escaping = e.escaping;
  // Sides traced again whose rays all kept their reference outcome: the same Earth hits as
  // the reference's, so their per-step lighting sums are copied (on the sample, half of the
  // sums a trial computed).
  std::vector<char>& replayed = e.replayed;
  replayed.assign(ns, 0);
  e.ref_lit = ref && ref->earth_lit_per_step.rows() == steps &&
                       ref->earth_lit_per_step.cols() == static_cast<Eigen::Index>(ref->key.size());
  const bool ref_lit = e.ref_lit;
  const PassContext pass = run.make_pass(ref ? &ref->earth_records : nullptr, &run.reused_earth_rays, &run.traced_earth_rays);
  std::atomic<int> replayed_by_cells{0};
  if (earth_fixed) {
    hits = earth_hits(scene, geo, sides, states[0].earth_direction_body, distance, radius, earth_rays, settings.earth_pilot_rays,
                      settings.seed, sobol, may_be_blocked, pass, ref ? &earth_todo : nullptr, /*flatten=*/false,
                      EarthReplay{ref, samples != nullptr || !ref_lit, &replayed_by_cells},
                      settings.earth_view_by_rays ? nullptr : &occ);
    if (ref)
      for (int s = 0; s < ns; ++s)
        if (!earth_todo[s]) {
          // Its rays are needed only to record them; its lighting sums come from the reference.
          if (samples || !ref_lit) hits.rays[s] = ref->earth[ref_of[s]];
          hits.view_factor[s] = ref->earth_view_factor[ref_of[s]];
          if (ref->earth_relative_error.size() == ref->earth_view_factor.size())
            hits.relative_error[s] = ref->earth_relative_error[ref_of[s]];
        }
    if (ref && ref_has_decisions)
      for (int s = 0; s < ns; ++s)
        replayed[s] = earth_todo[s] && hits.replayed[s] && ref_of[s] >= 0 &&
                      may_be_blocked[s] == ref->earth_may_be_blocked[ref_of[s]];
    if (samples) {
      samples->earth_view_factor = hits.view_factor;
      samples->earth_relative_error = hits.relative_error;
    }
    // A trial sums only the sides whose hits changed (lighting_per_step copies the others'
    // sums from the reference): the rest are not flattened.
    if (!samples)
      for (int s = 0; s < ns; ++s)
        if (e.sums_from_reference(s)) std::vector<std::pair<float, Eigen::Vector3f>>().swap(hits.rays[s]);
    hits.flatten(samples ? &samples->earth : nullptr);
  } else {
    // The same per-side counts as the cone sampling of the nadir case (per-node budgets,
    // noise-targeted boosts): a sun-pointing or inertial craft's Earth loads are as noisy
    // as a nadir one's at equal counts, or more (the cone's edge cuts these rays).
    auto dirs = escaping_directions(scene, geo, sides, earth_rays, settings.seed, sobol, pass,
                                    ref ? &earth_todo : nullptr);
    if (ref)
      for (int s = 0; s < ns; ++s)
        if (!earth_todo[s]) {
          dirs[s].clear();
          for (const auto& [w, d] : ref->earth[ref_of[s]]) dirs[s].push_back(d);
        }
    if (samples)
      for (int s = 0; s < ns; ++s)
        for (const auto& d : dirs[s]) samples->earth[s].emplace_back(1.0f / std::max(1, earth_rays[s]), d);
    escaping = pack_escaping(dirs, earth_rays);
  }
  if (reuse) reuse->earth_sides_replayed_by_cells = replayed_by_cells.load();
  if (pass.recording() && run.recorder.active()) samples->earth_records = run.take_records();
  return e;
}

// Earth fixed in body axes: per side, sum over its Earth hits of w max(0, n_E . sun) at
// every step at once (each hit read once, the steps in the inner, vectorisable loop).
// Returns steps x #sides.
Eigen::MatrixXf lighting_per_step(const LoadRun& run, const EarthSampling& e) {
  const int steps = run.steps, ns = run.ns;
  const std::vector<OrbitState>& states = run.states;
  const LoadSamples* ref = run.ref;
  const std::vector<int>& ref_of = run.ref_of;
  const EarthHits& hits = e.hits;
  Eigen::MatrixXf lit_per_step;
  std::vector<float> sx(steps), sy(steps), sz(steps);
  for (int k = 0; k < steps; ++k) {
    sx[k] = float(states[k].sun_direction_body.x());
    sy[k] = float(states[k].sun_direction_body.y());
    sz[k] = float(states[k].sun_direction_body.z());
  }
  lit_per_step = Eigen::MatrixXf::Zero(steps, ns);
  const float* nx = hits.normals.col(0).data();
  const float* ny = hits.normals.col(1).data();
  const float* nz = hits.normals.col(2).data();
  const float* w = hits.weights.data();
  tbb::parallel_for(tbb::blocked_range<int>(0, ns, 16), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s < range.end(); ++s) {
      float* acc = lit_per_step.col(s).data();
      if (e.sums_from_reference(s)) {
        lit_per_step.col(s) = ref->earth_lit_per_step.col(ref_of[s]);
        continue;
      }
      for (int r = hits.begin[s]; r < hits.begin[s + 1]; ++r) {
        const float wr = w[r], ax = nx[r], ay = ny[r], az = nz[r];
        for (int k = 0; k < steps; ++k) acc[k] += wr * std::max(0.0f, ax * sx[k] + ay * sy[k] + az * sz[k]);
      }
    }
  });
  return lit_per_step;
}

}  // namespace

void earth_loads(LoadRun& run) {
  const Environment& env = run.model.environment;
  const int steps = run.steps, ns = run.ns, num_nodes = run.num_nodes;
  const std::vector<OrbitState>& states = run.states;
  Loads& loads = run.loads;
  const double flux = run.flux;
  LoadSamples* samples = run.samples;
  const std::vector<Side>& geo = run.geo;
  const SurfaceSides& sides = run.sides;
  const Eigen::VectorXd& alpha = run.alpha;
  const Eigen::VectorXd& eps = run.eps;
  Eigen::MatrixXd& incident_albedo = run.incident_albedo;
  const EarthSampling e = sample_earth(run);
  const double distance = e.distance;
  const bool earth_fixed = e.earth_fixed;
  const EarthHits& hits = e.hits;
  const EscapingRays& escaping = e.escaping;
  Eigen::VectorXd view_factor, lit_sum(ns);
  Eigen::MatrixXf lit_per_step;  // steps x #sides
  if (earth_fixed) lit_per_step = lighting_per_step(run, e);
  if (samples && earth_fixed) samples->earth_lit_per_step = lit_per_step;
  for (int k = 0; k < steps; ++k) {
    const OrbitState& st = states[k];
    if (earth_fixed) {
      for (int s = 0; s < ns; ++s) lit_sum[s] = lit_per_step(k, s);
      view_factor = hits.view_factor;
    } else {
      earth_view_from_escaping(escaping, st.earth_direction_body, distance, run.model.environment.body_radius_m, st.sun_direction_body, view_factor, lit_sum);
    }
    for (int s = 0; s < ns; ++s) {
      if (view_factor[s] == 0.0) continue;
      incident_albedo(s, k) = env.albedo * flux * geo[s].area * lit_sum[s];
      const int node = sides.node[s];
      if (node < 0 || node >= num_nodes) continue;
      const double ir = eps[s] * env.earth_ir_flux_W_per_m2 * geo[s].area * view_factor[s];
      loads.earth_ir_W(node, k) += ir;
      if (earth_fixed && hits.relative_error.size() == ns)  // both scale with the unblocked share
        loads.sampling_standard_error_W(node, k) +=
            std::pow(hits.relative_error[s] * (ir + alpha[s] * incident_albedo(s, k)), 2);
      // note: the escaping rays' binomial error sqrt((1 - F) / (F N)) is left out of the
      // estimate, like the sun's shadow samples: on the sample in sun-pointing attitude it
      // asked for x8 Earth samples on the wings (4x the reduction's run time) to take the
      // measured noise floor from 0.020 K to 0.012 K (docs/thermal.md).
    }
  }
}

}  // namespace thermodec::load_rays
