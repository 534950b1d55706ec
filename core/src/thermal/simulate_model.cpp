#include "thermodec/thermal/simulate_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <vector>
#include <tbb/parallel_invoke.h>

#include "thermodec/common/errors.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/surface_sides.h"
#include "thermodec/thermal/network.h"
#include "thermodec/thermal/temperature_noise.h"

namespace thermodec {
namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Progress lines stamped with the seconds since the chain started. Lines always reach the
// caller's callback on the thread that built the Stamped (a front end's progress bar or console
// may only be touched there): lines from other threads (the couplings and the loads run side by
// side) wait in `pending` until that thread reports next or calls flush().
struct Stamped {
  explicit Stamped(const std::function<void(const std::string&)>& p) : progress(p) {}
  const std::function<void(const std::string&)>& progress;
  Clock::time_point t0 = Clock::now();
  std::thread::id owner = std::this_thread::get_id();
  mutable std::mutex lines;
  mutable std::vector<std::string> pending;
  void operator()(const std::string& what) const {
    if (!progress) return;
    char buf[32];
    std::snprintf(buf, sizeof buf, "[%7.2f s] ", seconds_since(t0));
    emit(buf + what);
  }
  void flush() const {
    if (progress) emit({});
  }

 private:
  void emit(std::string line) const {
    std::unique_lock<std::mutex> lock(lines);
    if (std::this_thread::get_id() != owner) {
      if (!line.empty()) pending.push_back(std::move(line));
      return;
    }
    std::vector<std::string> queued;
    queued.swap(pending);
    lock.unlock();
    for (const std::string& q : queued) progress(q);
    if (!line.empty()) progress(line);
  }
};

// chain_loads and solve_chain with progress stamped from `say`'s start (the whole chain's).
Loads loads_stamped(const ThermalModel& model, const RayScene& scene, const FaceViewFactors& view_factors,
                    const ModelSimulationSettings& settings, LoadSamples* record, const Stamped& say) {
  const ExternalLoadSettings s = chain_load_settings(model, settings);
  std::function<void(const std::string&)> sub;
  if (settings.progress) sub = [&](const std::string& m) { say("  " + m); };
  return external_loads(model, scene, view_factors.sides, s.solar_reflections ? &view_factors : nullptr, s, sub,
                        record);
}

SimulationResult solve_stamped(const ThermalModel& model, const NodeCouplings& couplings, const Loads& loads,
                               const ModelSimulationSettings& settings, const Stamped& say) {
  SimulationSettings solver = settings.solver;
  if (settings.progress) {
    const auto user_hook = solver.transient.on_orbit;
    solver.transient.on_orbit = [&say, user_hook](int orbit, double residual) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "  orbit %d: max |T(P) - T(0)| = %.3g K", orbit, residual);
      say(buf);
      if (user_hook) user_hook(orbit, residual);
    };
  }
  return simulate(model, couplings, loads, solver);
}
}  // namespace

ExternalLoadSettings chain_load_settings(const ThermalModel& model, const ModelSimulationSettings& settings) {
  ExternalLoadSettings s = settings.loads;
  s.seed = model.radiation.seed;
  s.planar_shadow_controls = settings.planar_strata;
  return s;
}

Loads chain_loads(const ThermalModel& model, const RayScene& scene, const FaceViewFactors& view_factors,
                  const ModelSimulationSettings& settings, LoadSamples* record) {
  return loads_stamped(model, scene, view_factors, settings, record, Stamped{settings.progress});
}

SimulationResult solve_chain(const ThermalModel& model, const NodeCouplings& couplings, const Loads& loads,
                             const ModelSimulationSettings& settings) {
  return solve_stamped(model, couplings, loads, settings, Stamped{settings.progress});
}

SimulationResult simulate_model(const ThermalModel& model, const ModelSimulationSettings& settings,
                                NodeCouplings* couplings_out) {
  const Stamped say{settings.progress};
  say("building ray scene (" + std::to_string(model.mesh.num_faces()) + " faces)");
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  // One set of side-to-side view factors serves both bands: IR couplings and solar reflections.
  // The IR couplings and the external loads side by side, as in a reduction's trials: each
  // alone leaves a core idle at times (the loads' many short per-step passes). The loads need
  // the view factors only for the solar reflections, added once both are done: the same sums
  // in the same order as within external_loads, so the same result bit for bit.
  const ExternalLoadSettings load_settings = chain_load_settings(model, settings);
  FaceViewFactors view_factors;
  NodeCouplings couplings;
  Loads loads;
  Eigen::MatrixXd solar_incident_W;
  tbb::parallel_invoke(
      [&] {
        say("view factors (" + std::to_string(model.radiation.rays_per_face) + " rays per face side)");
        RadiationSettings radiation = model.radiation;
        radiation.planar_strata = settings.planar_strata;
        view_factors = face_view_factors(scene, sides, radiation);
        say("IR Gebhart factors and node couplings");
        const int num_nodes = static_cast<int>(model.nodes.size());
        const Eigen::VectorXd eps = side_emissivity(model, sides);
        const GebhartFactors gebhart =
            gebhart_factors(view_factors, eps, node_groups(sides, num_nodes), num_nodes + 1);
        couplings = aggregate_couplings(view_factors, eps, gebhart, num_nodes);
        couplings.diagnostics.untraceable_faces = scene.num_skipped_faces();
      },
      [&] {
        say("external loads");
        std::function<void(const std::string&)> sub;
        if (settings.progress) sub = [&](const std::string& m) { say("  " + m); };
        loads = external_loads(model, scene, sides, nullptr, load_settings, sub, nullptr, nullptr, &solar_incident_W);
      });
  say.flush();  // the lines reported from the other thread, on the caller's
  if (load_settings.solar_reflections) {
    say("  solar reflections");
    add_solar_reflections(loads, model, view_factors.sides, view_factors, solar_incident_W);
  }
  say("thermal solve");
  ModelSimulationSettings full = settings;
  full.solver.orbit_sampling_error = true;  // summary.orbit_sampling_error_K of every full simulation
  SimulationResult r = solve_stamped(model, couplings, loads, full, say);
  say("done");
  if (couplings_out) *couplings_out = std::move(couplings);
  return r;
}

std::optional<SamplingBoosts> apply_noise_targeting(ThermalModel& model, const ModelSimulationSettings& settings,
                                                    const NoiseTargeting& targeting) {
  if (!(targeting.target_K > 0.0) || has_sampling_boosts(model)) return std::nullopt;
  if (settings.progress) settings.progress("sampling: estimating each node's Monte Carlo noise");
  SamplingBoosts b = decide_sampling_boosts(model, settings, targeting.target_K, targeting.budget, targeting.max_samples);
  for (std::size_t k = 0; k < b.boost.size() && k < model.nodes.size(); ++k) model.nodes[k].sampling_boost = b.boost[k];
  if (settings.progress) settings.progress(b.describe(model.nodes));
  return b;
}

FrontEndSimulation simulate_as_front_end(ThermalModel& model, const ModelSimulationSettings& settings,
                                         const NoiseTargeting& targeting) {
  FrontEndSimulation out;
  out.sampling = apply_noise_targeting(model, settings, targeting);
  out.result = simulate_model(model, settings, &out.couplings);
  return out;
}

bool has_sampling_boosts(const ThermalModel& model) {
  for (const Node& n : model.nodes)
    if (n.sampling_boost != Node::SamplingBoost{}) return true;
  return false;
}

bool SamplingBoosts::any() const {
  for (const auto& b : boost)
    if (b != Node::SamplingBoost{}) return true;
  return false;
}

std::string SamplingBoosts::summary(const std::vector<Node>& nodes) const {
  std::string out;
  char buf[64];
  // A thinned kind carries the same multiplier < 1 on every node: said once, not per node.
  const double ir_thin = !boost.empty() && boost.front().ir < 1.0 ? boost.front().ir : 1.0;
  const double loads_thin = !boost.empty() && boost.front().loads < 1.0 ? boost.front().loads : 1.0;
  for (std::size_t k = 0; k < boost.size() && k < nodes.size(); ++k) {
    const bool ir = boost[k].ir != 1.0 && ir_thin == 1.0, loads = boost[k].loads != 1.0 && loads_thin == 1.0;
    if (!ir && !loads) continue;
    out += (out.empty() ? "" : ", ") + nodes[k].name;
    if (ir) out += (std::snprintf(buf, sizeof buf, " IR x%g", boost[k].ir), buf);
    if (loads) out += (std::snprintf(buf, sizeof buf, " loads x%g", boost[k].loads), buf);
  }
  if (ir_thin != 1.0) out += (std::snprintf(buf, sizeof buf, "%severy node IR x%g", out.empty() ? "" : ", ", ir_thin), buf);
  if (loads_thin != 1.0)
    out += (std::snprintf(buf, sizeof buf, "%severy node loads x%g", out.empty() ? "" : ", ", loads_thin), buf);
  return out;
}

std::string SamplingBoosts::describe(const std::vector<Node>& nodes) const {
  // The largest estimate of each kind and its node: what decided the boosts or the thinning.
  std::string largest;
  char buf[200];
  for (const auto* kind : {&ir_standard_error_K, &load_standard_error_K}) {
    Eigen::Index k = 0;
    if (kind->size() == 0 || kind->size() > static_cast<Eigen::Index>(nodes.size())) continue;
    const double v = kind->maxCoeff(&k);
    std::snprintf(buf, sizeof buf, "%s %.2g K (%s)", kind == &ir_standard_error_K ? "IR" : ", loads", v,
                  nodes[k].name.c_str());
    largest += buf;
  }
  if (!largest.empty()) largest = "; largest estimated error " + largest;
  if (!any()) return "sampling: no node needs more samples" + largest;
  std::snprintf(buf, sizeof buf, "sampling: target %.3g K, %+.0f %% IR rays (%+.3g), %+.0f %% sun/Earth samples (%+.3g): ",
                target_K, 100.0 * extra_ir_rays, extra_ir_rays * ir_rays, 100.0 * extra_load_samples,
                extra_load_samples * load_samples);
  return buf + summary(nodes) + largest;
}

namespace {
// extra_ir_rays / extra_load_samples of out.boost: the samples added (< 0: removed) over the
// unboosted totals, from each node's unboosted IR rays and sun + Earth samples.
void count_extra_samples(SamplingBoosts& out, const std::vector<double>& ir_rays,
                         const std::vector<double>& load_samples) {
  double extra_ir = 0.0, extra_load = 0.0;
  for (std::size_t i = 0; i < out.boost.size(); ++i) {
    extra_ir += ir_rays[i] * (out.boost[i].ir - 1.0);
    extra_load += load_samples[i] * (out.boost[i].loads - 1.0);
  }
  out.extra_ir_rays = out.ir_rays > 0.0 ? extra_ir / out.ir_rays : 0.0;
  out.extra_load_samples = out.load_samples > 0.0 ? extra_load / out.load_samples : 0.0;
}

// A kind (IR rays, sun and Earth samples) none of whose nodes needs a boost is divided by its
// common thinning factor (noise_targeted_thinning) when `min_boost` < 1 allows it.
void thin_oversampled_kinds(SamplingBoosts& out, double min_boost, const std::vector<double>& ir_rays,
                            const std::vector<double>& load_samples) {
  if (!(min_boost < 1.0)) return;
  bool ir_boosted = false, loads_boosted = false;
  for (const auto& b : out.boost) {
    ir_boosted = ir_boosted || b.ir != 1.0;
    loads_boosted = loads_boosted || b.loads != 1.0;
  }
  const double ir = ir_boosted ? 1.0 : noise_targeted_thinning(out.ir_standard_error_K, out.target_K, min_boost);
  const double loads =
      loads_boosted ? 1.0 : noise_targeted_thinning(out.load_standard_error_K, out.target_K, min_boost);
  for (auto& b : out.boost) {
    if (ir != 1.0) b.ir = ir;
    if (loads != 1.0) b.loads = loads;
  }
  count_extra_samples(out, ir_rays, load_samples);
}
}  // namespace

SamplingBoosts decide_sampling_boosts(const ThermalModel& model, const ModelSimulationSettings& settings,
                                      double target_K, double max_extra, double max_extra_samples, double min_boost) {
  if (!(target_K > 0.0)) throw InvalidInput("noise target must be > 0 K");
  if (!(max_extra >= 0.0) || !(max_extra_samples >= 0.0)) throw InvalidInput("noise budget must be >= 0");
  SamplingBoosts out;
  NodeCouplings couplings;
  out.unboosted = simulate_model(model, settings, &couplings);
  const ThermalNetwork net = thermal_network(model, couplings);
  const Eigen::MatrixXd& T = out.unboosted.temperature_K;
  out.ir_standard_error_K = temperature_standard_error_K(net, couplings, T);
  // Steady runs solve the orbit-averaged loads at one time: the orbit mean's error (Loads).
  Eigen::MatrixXd load_se = out.unboosted.loads.sampling_standard_error_W;
  const Eigen::VectorXd& mean_se = out.unboosted.loads.orbit_mean_standard_error_W;
  if (load_se.cols() != T.cols() && T.cols() == 1 && load_se.cols() > 0)
    load_se = mean_se.size() == load_se.rows() ? Eigen::MatrixXd(mean_se) : Eigen::MatrixXd(load_se.rowwise().mean());
  out.load_standard_error_K = load_se.rows() == T.rows() && load_se.cols() == T.cols()
                                  ? temperature_standard_error_from_loads_K(net, T, load_se)
                                  : Eigen::VectorXd::Zero(T.rows());
  // Samples per node at the model's counts: what a boost multiplies.
  const SurfaceSides sides = surface_sides(model);
  const Eigen::VectorXi ir = side_ray_counts(sides, model.radiation);
  const ExternalLoadSettings& ls = settings.loads;
  const Eigen::VectorXi sun = rays_per_side_of_node(sides, ls.sun_rays_per_face, ls.sun_min_rays_per_node, sides.load_boost);
  const Eigen::VectorXi earth =
      rays_per_side_of_node(sides, ls.earth_rays_per_face, ls.earth_min_rays_per_node, sides.load_boost);
  const std::size_t n = model.nodes.size();
  std::vector<double> ir_rays(n, 0.0), load_samples(n, 0.0);
  double ir_total = 0.0, load_total = 0.0;
  for (int s = 0; s < sides.size(); ++s) {
    ir_total += ir[s];
    load_total += sun[s] + earth[s];
    if (sides.node[s] < 0) continue;
    ir_rays[sides.node[s]] += ir[s];
    load_samples[sides.node[s]] += sun[s] + earth[s];
  }
  out.ir_rays = ir_total;
  out.load_samples = load_total;
  // Each kind's extra samples: at most max_extra x its total and at most max_extra_samples.
  const double ir_cap = std::min(max_extra, ir_total > 0.0 ? max_extra_samples / ir_total : max_extra);
  const double load_cap = std::min(max_extra, load_total > 0.0 ? max_extra_samples / load_total : max_extra);
  out.target_K = target_K;
  for (int attempt = 0; attempt < 64; ++attempt, out.target_K *= std::sqrt(2.0)) {
    const std::vector<double> b_ir = noise_targeted_sampling_boosts(out.ir_standard_error_K, out.target_K);
    const std::vector<double> b_load = noise_targeted_sampling_boosts(out.load_standard_error_K, out.target_K);
    out.boost.assign(n, {});
    for (std::size_t i = 0; i < n; ++i) out.boost[i] = {b_ir[i], b_load[i]};
    count_extra_samples(out, ir_rays, load_samples);
    if (out.extra_ir_rays <= ir_cap && out.extra_load_samples <= load_cap) break;
  }
  thin_oversampled_kinds(out, min_boost, ir_rays, load_samples);
  return out;
}

void apply_bare_mesh_ray_budgets(ThermalModel& model, ModelSimulationSettings& settings) {
  if (!model.mesh_cleanup) return;
  const double faces = std::max(1, model.mesh.num_faces());
  auto clamp = [](double x, int lo, int hi) { return static_cast<int>(std::min<double>(hi, std::max<double>(lo, std::round(x)))); };
  model.radiation.rays_per_face = clamp(kBareMeshIrRays / faces, 1000, 4000);
  settings.loads.sun_rays_per_face = clamp(kBareMeshSunRays / faces, 256, 1024);
  settings.loads.sun_min_rays_per_node = std::max(settings.loads.sun_min_rays_per_node, 400000);
}

NoiseFloor noise_floor(const ThermalModel& model, int runs, const ModelSimulationSettings& settings,
                       const SimulationResult* first) {
  if (runs < 2) throw InvalidInput("noise floor needs at least 2 runs");
  std::vector<std::uint64_t> seeds;
  std::vector<SimulationResult> results;
  std::vector<double> run_time_s;
  ThermalModel m = model;
  for (int k = 0; k < runs; ++k) {
    m.radiation.seed = model.radiation.seed + static_cast<std::uint64_t>(k);
    seeds.push_back(m.radiation.seed);
    if (k == 0 && first) {
      results.push_back(*first);
      continue;
    }
    const auto t0 = Clock::now();
    results.push_back(simulate_model(m, settings));
    run_time_s.push_back(seconds_since(t0));
  }
  NoiseFloor out = noise_floor_of(std::move(results), std::move(seeds));
  out.run_time_s = std::move(run_time_s);
  return out;
}

NoiseFloor noise_floor_of(std::vector<SimulationResult> results, std::vector<std::uint64_t> seeds) {
  const int runs = static_cast<int>(results.size());
  if (runs < 2) throw InvalidInput("noise floor needs at least 2 runs");
  if (seeds.size() != results.size()) throw InvalidInput("noise floor: one seed per run expected");
  NoiseFloor out;
  out.seeds = std::move(seeds);
  for (int i = 0; i < runs; ++i)
    for (int j = i + 1; j < runs; ++j) {
      out.pairs.emplace_back(i, j);
      out.differences.push_back(compare_results(results[i], results[j]));
      const auto& by_node = out.differences.back().per_node;
      if (out.per_node.empty())
        for (const auto& d : by_node) out.per_node.push_back({d.node, -1.0, 0.0, {i, j}});
      for (std::size_t n = 0; n < by_node.size() && n < out.per_node.size(); ++n)
        if (by_node[n].max_abs_K > out.per_node[n].max_abs_K)
          out.per_node[n] = {by_node[n].node, by_node[n].max_abs_K, by_node[n].time_s, {i, j}};
      if (out.differences.back().max_abs_K >= out.worst.max_abs_K) {
        out.worst = out.differences.back();
        out.worst_pair = {i, j};
      }
    }
  std::vector<double> v;
  for (const auto& d : out.differences) v.push_back(d.max_abs_K);
  std::sort(v.begin(), v.end());
  out.median_abs_K = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  out.first = std::move(results.front());
  return out;
}

}  // namespace thermodec
