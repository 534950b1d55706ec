// External loads, the driver: direct sun with self-shadowing (direct_sun.cpp), Earth albedo and
// IR through ray-traced face-to-Earth view factors (earth_loads.cpp, earth_cone.cpp,
// escaping_rays.cpp), and solar-band diffuse reflections (solar_reflections.cpp). A trial of
// the reduction driver reuses a reference run's samples where its change cannot reach them
// (change_reach.h, ray_records.h): the result equals a full run bit for bit.
// The paper (Sec. III) lists the three effects that make a face's incident solar power:
// its angle to the source, occlusion by other faces, and reflections from other faces.
#include "thermodec/environment/external_loads.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "load_run.h"
#include "sun_kinks.h"
#include "thermodec/common/errors.h"

namespace thermodec {
namespace load_rays {

LoadRun::LoadRun(const ThermalModel& model_in, const RayScene& scene_in, const SurfaceSides& sides_in,
                 const ExternalLoadSettings& settings_in, const std::function<void(const std::string&)>& progress_in,
                 LoadSamples* samples_in, LoadReuse* reuse_in)
    : model(model_in), scene(scene_in), sides(sides_in), settings(settings_in), progress(progress_in),
      samples(samples_in), reuse(reuse_in), ref(reuse_in ? reuse_in->reference : nullptr) {
  const Environment& env = model.environment;
  num_nodes = static_cast<int>(model.nodes.size());
  ns = sides.size();
  geo = side_geometry(scene.mesh(), sides);
  alpha = side_absorptivity(model, sides);
  eps = side_emissivity(model, sides);
  if (settings.planar_shadow_controls && !ref && ns > 0)
    shadow_hulls = planar_node_hulls(scene.mesh(), sides, sides.node.maxCoeff() + 1);

  orbit = env.type == EnvironmentType::orbit;
  steps = orbit ? (settings.steps_per_orbit > 0 ? settings.steps_per_orbit : model.analysis.steps_per_orbit) : 1;
  if (orbit && steps < 2) throw InvalidInput("analysis.steps_per_orbit must be >= 2 for an orbit");
  loads.period_s = orbit ? orbit_period_s(env) : 0.0;
  loads.times_s = Eigen::VectorXd::LinSpaced(steps, 0.0, loads.period_s * (steps - 1) / steps);
  if (!orbit) loads.times_s = Eigen::VectorXd::Zero(1);
  loads.in_shadow.assign(steps, 0);
  for (auto* m : {&loads.solar_W, &loads.albedo_W, &loads.earth_ir_W, &loads.reflected_solar_W,
                 &loads.sampling_standard_error_W})
    *m = Eigen::MatrixXd::Zero(num_nodes, steps);

  if (orbit) {
    flux = solar_flux_W_per_m2(env);
    for (int k = 0; k < steps; ++k) states.push_back(orbit_state(env, loads.times_s[k]));
  } else {
    flux = env.solar_flux_W_per_m2;
    if (!(flux >= 0.0)) throw InvalidInput("environment.solar_flux_W_per_m2 must be >= 0");
    if (!(env.sun_direction.norm() > 0.0)) throw InvalidInput("environment.sun_direction must be non-zero");
    OrbitState st;
    st.sun_direction_body = env.sun_direction.normalized();
    states.push_back(st);
  }
  positions = steps;
  // Sunlit knots: the sunlit side of each shadow switch, and the kinks of the direct sun where a
  // face side turns edge-on to it, traced like more positions (after them).
  if (orbit && flux > 0.0) {
    std::vector<std::pair<double, bool>> knots;  // (time, eclipse edge: forced sunlit)
    if (ref && ref->knot_times_s.size() == static_cast<Eigen::Index>(ref->knot_is_edge.size())) {
      // A trial traces its reference's knots: its steps must match the reference's.
      for (Eigen::Index e = 0; e < ref->knot_times_s.size(); ++e)
        knots.emplace_back(ref->knot_times_s[e], ref->knot_is_edge[static_cast<std::size_t>(e)] != 0);
    } else {
      if (settings.eclipse_edges) {
        const Eigen::VectorXd sw = eclipse_switch_times_s(env, loads.period_s);
        for (Eigen::Index e = 0; e < sw.size(); ++e) knots.emplace_back(sw[e], true);
      }
      if (settings.kink_knot_threshold_K > 0.0) {
        const std::vector<int> node_of_side(sides.node.data(), sides.node.data() + sides.node.size());
        const int cap = settings.max_kink_knots >= 0 ? settings.max_kink_knots : positions;
        for (const double t : sun_kink_times_s(model, geo, node_of_side, alpha, flux, positions,
                                               settings.kink_knot_threshold_K, cap))
          knots.emplace_back(t, false);
      }
    }
    std::sort(knots.begin(), knots.end());
    knot_times_s.resize(static_cast<Eigen::Index>(knots.size()));
    knot_is_edge.assign(knots.size(), 0);
    for (std::size_t e = 0; e < knots.size(); ++e) {
      knot_times_s[static_cast<Eigen::Index>(e)] = knots[e].first;
      knot_is_edge[e] = knots[e].second;
      OrbitState st = orbit_state(env, knots[e].first);
      if (knots[e].second) st.in_shadow = false;
      states.push_back(st);
    }
    steps += static_cast<int>(knots.size());
    loads.in_shadow.assign(steps, 0);
    for (auto* m : {&loads.solar_W, &loads.albedo_W, &loads.earth_ir_W, &loads.reflected_solar_W,
                   &loads.sampling_standard_error_W})
      *m = Eigen::MatrixXd::Zero(num_nodes, steps);
  }

  // Reuse: map sides to the reference's by identity; a side is reusable for a ray family only
  // if the family cannot reach the changed region (conservative sphere tests, ChangeReach).
  ref_of.assign(ns, -1);
  sun_rays = rays_per_side_of_node(sides, settings.sun_rays_per_face, settings.sun_min_rays_per_node, sides.load_boost);
  earth_rays = rays_per_side_of_node(sides, settings.earth_rays_per_face, settings.earth_min_rays_per_node, sides.load_boost);
  if (flux > 0.0) shadow_division = shadow_pass_division(model, settings, sun_passes(states));
  sun_rays_per_pass = shadow_rays_per_pass(sun_rays, shadow_division);
  own_shadow_points = shadow_division > 1 || (orbit && settings.transient_shadow_passes &&
                                              model.analysis.type != AnalysisType::steady && flux > 0.0);
  sun_variance = Eigen::MatrixXd::Zero(num_nodes, steps);
  // One Sobol table for every pass (the largest count any side or pilot draws).
  int max_rays = std::max({settings.sun_pilot_rays, settings.earth_pilot_rays, settings.earth_rays_per_face, 1});
  if (ns > 0) max_rays = std::max({max_rays, sun_rays.maxCoeff(), earth_rays.maxCoeff()});
  table = tracing::shared_sobol_table(max_rays);
  occ = occluders(geo, sides);
  if (ref) {
    if (ref->sunlit.cols() != steps || static_cast<int>(ref->key.size()) != ref->sunlit.rows())
      throw InvalidInput("external loads: reference samples are for another environment or step count");
    std::unordered_map<std::uint64_t, int> index;
    for (size_t i = 0; i < ref->key.size(); ++i) index.emplace(ref->key[i], static_cast<int>(i));
    for (int s = 0; s < ns; ++s) {
      const auto it = index.find(sides.key[s]);
      if (it != index.end()) ref_of[s] = it->second;
    }
  }
  reach.emplace(geo, reuse);
  // Per-ray reuse: a side with the same sample counts as its reference twin reads the
  // reference's record of its rays (same rays, same order); the others trace everything.
  change_box = ref ? ChangeBox(reuse->changed_region, reuse->changed_faces, scene.mesh().num_faces()) : ChangeBox();
  per_ray_reuse = ref && ref->per_ray;
  ref_side.assign(ns, -1);
  if (per_ray_reuse)
    for (int s = 0; s < ns; ++s) ref_side[s] = same_counts(s) ? ref_of[s] : -1;
  // Recording (reference runs only: a run that itself reuses records nothing per ray).
  recorder.budget = settings.ray_record_budget_bytes;
  recorder.geometry_budget = settings.earth_ray_geometry_budget_bytes;
  record = samples && !reuse;
}

bool LoadRun::same_counts(int s) const {
  return ref_of[s] >= 0 && ref->sun_rays.size() == static_cast<Eigen::Index>(ref->key.size()) &&
         ref->sun_rays[ref_of[s]] == sun_rays[s] && ref->earth_rays[ref_of[s]] == earth_rays[s];
}

RayRecords LoadRun::take_records() {
  RayRecords r = pack_records(recorded);
  std::vector<SideRays>().swap(recorded);
  return r;
}

PassContext LoadRun::make_pass(const RayRecords* ref_records, std::atomic<long>* reused_rays,
                               std::atomic<long>* traced_rays) {
  PassContext pass;
  pass.change = &change_box;
  if (per_ray_reuse && ref_records && !ref_records->empty()) {
    pass.ref_records = ref_records;
    pass.ref_side = &ref_side;
  }
  if (record && recorder.active()) {
    recorded.assign(ns, SideRays{});
    pass.record = &recorded;
    pass.recorder = &recorder;
  }
  pass.reused_rays = reused_rays;
  pass.traced_rays = traced_rays;
  return pass;
}

namespace {

void clear_samples(LoadRun& run) {
  LoadSamples* samples = run.samples;
  const int ns = run.ns, steps = run.steps;
  samples->key = run.sides.key;
  samples->sunlit = Eigen::MatrixXd::Zero(ns, steps);
  samples->sun_rays = run.sun_rays;
  samples->earth_rays = run.earth_rays;
  samples->earth.assign(ns, {});
  samples->earth_view_factor = Eigen::VectorXd::Zero(ns);
  samples->earth_relative_error = Eigen::VectorXd::Zero(ns);
  samples->sun_records.assign(steps, RayRecords{});
  samples->earth_records = RayRecords{};
  samples->per_ray = false;
  samples->earth_may_be_blocked.clear();
  samples->knot_times_s = run.knot_times_s;
  samples->knot_is_edge = run.knot_is_edge;
}

// Reuse counters, records kept or dropped, and the absorbed solar and albedo per node.
void finish_run(LoadRun& run) {
  LoadReuse* reuse = run.reuse;
  LoadSamples* samples = run.samples;
  Loads& loads = run.loads;
  const int steps = run.steps, ns = run.ns, num_nodes = run.num_nodes;
  const std::vector<OrbitState>& states = run.states;
  if (reuse) {
    reuse->reused_sun_rays += run.reused_sun_rays;
    reuse->traced_sun_rays += run.traced_sun_rays;
    reuse->reused_earth_rays += run.reused_earth_rays;
    reuse->traced_earth_rays += run.traced_earth_rays;
  }
  if (run.record) {
    samples->per_ray = run.recorder.active();
    if (!samples->per_ray) {  // over budget: keep none (trials use the per-side tests)
      samples->sun_records.assign(steps, RayRecords{});
      samples->earth_records = RayRecords{};
    }
  }
  if (samples) samples->earth_fixed = !run.orbit || earth_fixed_in_body(states);

  // Variances summed above: the Earth rays' in the loads, the shadow samples' in run.sun_variance.
  const Eigen::MatrixXd earth_sd = loads.sampling_standard_error_W.cwiseSqrt();
  loads.sampling_standard_error_W = (loads.sampling_standard_error_W + run.sun_variance).cwiseSqrt();
  // The orbit mean's: the Earth rays are the same at every step (their errors add as standard
  // deviations); shadow passes with their own points are independent (variances add).
  // Over the positions only (the knots, after them, are not orbit samples).
  const int S = run.positions;
  if (run.own_shadow_points)
    loads.orbit_mean_standard_error_W = (run.sun_variance.leftCols(S).rowwise().sum() / double(S * S) +
                                         earth_sd.leftCols(S).rowwise().mean().cwiseAbs2())
                                            .cwiseSqrt();
  else
    loads.orbit_mean_standard_error_W = loads.sampling_standard_error_W.leftCols(S).rowwise().mean();
  for (int s = 0; s < ns; ++s) {
    const int node = run.sides.node[s];
    if (node < 0 || node >= num_nodes) continue;
    loads.solar_W.row(node) += run.alpha[s] * run.incident_direct.row(s);
    loads.albedo_W.row(node) += run.alpha[s] * run.incident_albedo.row(s);
  }
}

// Moves the knots' columns (after the positions') into Loads::knot_*.
void split_knots(LoadRun& run) {
  Loads& loads = run.loads;
  const int S = run.positions, E = run.steps - run.positions;
  if (E == 0) return;
  loads.knot_times_s = run.knot_times_s;
  loads.knot_solar_W = loads.solar_W.rightCols(E);
  loads.knot_albedo_W = loads.albedo_W.rightCols(E);
  loads.knot_earth_ir_W = loads.earth_ir_W.rightCols(E);
  loads.knot_reflected_solar_W = loads.reflected_solar_W.rightCols(E);
  for (auto* m : {&loads.solar_W, &loads.albedo_W, &loads.earth_ir_W, &loads.reflected_solar_W,
                 &loads.sampling_standard_error_W})
    *m = Eigen::MatrixXd(m->leftCols(S));
  loads.in_shadow.resize(S);
}

}  // namespace
}  // namespace load_rays

int shadow_pass_division(int shadow_passes) {
  return shadow_passes <= 1 ? 1 : std::max(1, static_cast<int>(std::lround(std::pow(double(shadow_passes), 2.0 / 3.0))));
}

int shadow_pass_division(const ThermalModel& model, const ExternalLoadSettings& settings, int shadow_passes) {
  const bool divided = settings.steady_shadow_passes && model.analysis.type == AnalysisType::steady &&
                       model.environment.type == EnvironmentType::orbit;
  return divided ? shadow_pass_division(shadow_passes) : 1;
}

Eigen::VectorXi shadow_rays_per_pass(const Eigen::VectorXi& rays, int division) {
  if (division <= 1) return rays;
  Eigen::VectorXi out(rays.size());
  for (Eigen::Index s = 0; s < rays.size(); ++s)
    out[s] = std::max(std::min(rays[s], 16), (rays[s] + division - 1) / division);
  return out;
}

Loads external_loads(const ThermalModel& model, const RayScene& scene, const SurfaceSides& sides,
                     const FaceViewFactors* view_factors, const ExternalLoadSettings& settings,
                     const std::function<void(const std::string&)>& progress, LoadSamples* samples,
                     LoadReuse* reuse, Eigen::MatrixXd* solar_incident_W) {
  if (settings.sun_rays_per_face < 1) throw InvalidInput("sun_rays_per_face must be >= 1");
  if (settings.earth_pilot_rays < 1) throw InvalidInput("earth_pilot_rays must be >= 1");
  if (settings.sun_pilot_rays < 1) throw InvalidInput("sun_pilot_rays must be >= 1");
  if (settings.earth_rays_per_face < 1) throw InvalidInput("earth_rays_per_face must be >= 1");
  load_rays::LoadRun run(model, scene, sides, settings, progress, samples, reuse);
  if (samples) load_rays::clear_samples(run);
  run.incident_direct = Eigen::MatrixXd::Zero(run.ns, run.steps);
  run.incident_albedo = Eigen::MatrixXd::Zero(run.ns, run.steps);

  load_rays::direct_sun_loads(run);
  // Earth: cone rays once if the Earth is fixed in body axes (nadir), else escaping
  // hemisphere rays once, intersected with the Earth's cone at every step.
  if (run.orbit) load_rays::earth_loads(run);
  load_rays::finish_run(run);

  const Eigen::MatrixXd incident = run.incident_direct + run.incident_albedo;
  if (settings.solar_reflections && view_factors) {
    if (progress) progress("solar reflections");
    add_solar_reflections(run.loads, model, sides, *view_factors, incident, run.ref, samples);
  }
  load_rays::split_knots(run);
  if (solar_incident_W) *solar_incident_W = incident;
  return std::move(run.loads);
}

}  // namespace thermodec
