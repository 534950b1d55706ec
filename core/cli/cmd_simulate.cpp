// `thermodec simulate MODEL --json OUT [--plot OUT.png] [--noise-floor]`
#include <chrono>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/exchange/exported_network.h"
#include "thermodec/exchange/write_vtk_series.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/common/output_paths.h"
#include "thermodec/report/plot.h"
#include "thermodec/thermal/result_json.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec::cli {
namespace {

struct SimulateOptions {
  std::string model;
  std::string json_out;
  std::string plot_out;
  std::string vtk_dir;  // ParaView series (exchange/write_vtk_series.h)
  bool noise_floor = false;
  int noise_runs = 3;
  bool quiet = false;
  int rays_per_face = 0;  // 0 = the model's radiation.rays_per_face
  bool raw_mesh = false;
  ExternalLoadSettings loads;
  bool sun_rays_set = false;
  NoiseTargeting noise;  // the core's defaults, shared by every front end (thermal/simulate_model.h)
  long long seed = -1;          // -1 = the model's radiation.seed
  int load_positions = 0;       // 0 = the model's analysis.steps_per_orbit
  double time_tolerance_K = 0;  // 0 = the model's analysis.time_tolerance_K
};

void run_simulate(const SimulateOptions& o) {
  ModelLoadOptions load = model_load_options();
  load.clean_bare_mesh = !o.raw_mesh;
  ThermalModel model = load_model(o.model, load);
  ModelSimulationSettings settings;
  settings.loads = o.loads;
  if (!o.raw_mesh) apply_bare_mesh_ray_budgets(model, settings);
  if (o.sun_rays_set) settings.loads.sun_rays_per_face = o.loads.sun_rays_per_face;
  if (model.mesh_cleanup && !o.quiet) std::cout << "bare mesh cleanup:\n" << model.mesh_cleanup->summary();
  if (o.rays_per_face > 0) model.radiation.rays_per_face = o.rays_per_face;
  if (o.seed >= 0) model.radiation.seed = static_cast<std::uint64_t>(o.seed);
  if (o.load_positions > 0) model.analysis.steps_per_orbit = o.load_positions;
  if (o.time_tolerance_K > 0) model.analysis.time_tolerance_K = o.time_tolerance_K;
  const std::vector<std::filesystem::path> inputs{o.model, model.mesh_path};
  // Refuse before the work, not after it.
  if (!o.json_out.empty()) check_output_file(o.json_out, "--json", {".json"}, inputs);
  if (!o.plot_out.empty()) check_output_file(o.plot_out, "--plot", {".png"}, inputs);
  if (!o.json_out.empty() && !o.plot_out.empty() && same_file(o.json_out, o.plot_out))
    throw InvalidInput("--json and --plot name the same file " + o.json_out);
  const auto start = std::chrono::steady_clock::now();
  std::error_code ec;
  if (!o.vtk_dir.empty() && std::filesystem::exists(o.vtk_dir, ec) && !std::filesystem::is_directory(o.vtk_dir, ec))
    throw InvalidInput("--vtk " + o.vtk_dir + " is a file; it must be a folder (created if missing)");
  if (!o.vtk_dir.empty() && o.noise_floor) throw InvalidInput("--vtk writes one simulation; it does not combine with --noise-floor");
  guard_simulation_cost("simulate", check_front_end_simulation_cost(model, settings, o.noise), o.quiet);
  if (!o.quiet) settings.progress = [](const std::string& m) { std::cerr << "simulate: " << m << "\n"; };

  nlohmann::json extra;
  // Noise-targeted sampling: one simulation at the model's counts estimates each node's
  // temperature noise; the nodes above the target get more samples (docs/thermal.md).
  if (const auto b = apply_noise_targeting(model, settings, o.noise)) {
    nlohmann::json boosts = nlohmann::json::object(), estimates = nlohmann::json::object();
    for (std::size_t k = 0; k < b->boost.size(); ++k) {
      estimates[model.nodes[k].name] = {{"ir", b->ir_standard_error_K[k]}, {"loads", b->load_standard_error_K[k]}};
      if (b->boost[k] != Node::SamplingBoost{})
        boosts[model.nodes[k].name] = {{"ir", b->boost[k].ir}, {"loads", b->boost[k].loads}};
    }
    extra["sampling"] = {{"noise_target_K", b->target_K}, {"extra_ir_rays", b->extra_ir_rays},
                         {"extra_load_samples", b->extra_load_samples}, {"sampling_boost", boosts},
                         {"estimated_standard_error_K", estimates}};
  }
  SimulationResult result;
  if (o.noise_floor) {
    const NoiseFloor nf = noise_floor(model, o.noise_runs, settings);
    result = nf.first;
    std::printf("noise floor over %d seeds (%llu..%llu), all %zu pairs: max |dT| = %.4g K at node %s, t = %.1f s "
                "(seeds %llu and %llu); median pair %.4g K\n",
                o.noise_runs, (unsigned long long)nf.seeds.front(), (unsigned long long)nf.seeds.back(),
                nf.pairs.size(), nf.worst.max_abs_K, nf.worst.node.c_str(), nf.worst.time_s,
                (unsigned long long)nf.seeds[nf.worst_pair.first], (unsigned long long)nf.seeds[nf.worst_pair.second],
                nf.median_abs_K);
    std::string by_node;
    nlohmann::json per_node = nlohmann::json::object();
    for (const auto& w : nf.per_node) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%s %.2g", by_node.empty() ? "" : ", ", w.node.c_str(), w.max_abs_K);
      by_node += buf;
      per_node[w.node] = {{"max_abs_dT_K", w.max_abs_K},
                          {"time_s", w.time_s},
                          {"seeds", {nf.seeds[w.pair.first], nf.seeds[w.pair.second]}}};
    }
    std::printf("worst pair per node [K]: %s\n", by_node.c_str());
    double total = 0.0;
    for (double t : nf.run_time_s) total += t;
    std::printf("run time: %.2f s per simulation (mean of %d)\n", total / nf.run_time_s.size(),
                int(nf.run_time_s.size()));
    extra["noise_floor"] = {{"seeds", nf.seeds},
                            {"pairs", nf.pairs.size()},
                            {"max_abs_dT_K", nf.worst.max_abs_K},
                            {"median_pair_max_abs_dT_K", nf.median_abs_K},
                            {"worst_seeds", {nf.seeds[nf.worst_pair.first], nf.seeds[nf.worst_pair.second]}},
                            {"node", nf.worst.node},
                            {"time_s", nf.worst.time_s},
                            {"per_node", per_node},
                            {"run_time_s", nf.run_time_s}};
  } else {
    NodeCouplings couplings;
    result = simulate_model(model, settings, &couplings);
    if (!o.vtk_dir.empty()) {
      const auto pvd = write_vtk_series(o.vtk_dir, std::filesystem::path(o.model).stem().string(), model,
                                        exported_network(model, couplings, result, o.model), inputs);
      if (!o.quiet) std::cerr << "simulate: wrote " << pvd.string() << "\n";
    }
  }
  if (!o.quiet) {
    const bool noise = result.noise_K.size() == static_cast<Eigen::Index>(result.nodes.size());
    for (size_t i = 0; i < result.nodes.size(); ++i) {
      std::printf("%-16s min %8.2f K  mean %8.2f K  max %8.2f K", result.nodes[i].c_str(),
                  result.temperature_K.row(i).minCoeff(), result.temperature_K.row(i).mean(),
                  result.temperature_K.row(i).maxCoeff());
      if (noise) std::printf("  noise +- %.2g K", result.noise_K[i]);
      std::printf("\n");
    }
    // The error budget: the time integration's and the orbit sampling's (max over nodes and times);
    // the sampling noise is per node above (one standard deviation, docs/thermal.md).
    if (result.transient) std::printf("time integration error <= %.2g K", result.time_error_K);
    if (result.loads.period_s > 0.0)
      std::printf("%sorbit sampling error ~ %.2g K (%d positions)\n", result.transient ? ", " : "",
                  result.orbit_sampling_error_K, model.analysis.steps_per_orbit);
    else if (result.transient)
      std::printf("\n");
  }
  nlohmann::json j = result_to_json(result);
  j["model"] = o.model;
  const auto used = environment_analysis_json(model);
  for (const auto& [key, value] : used.items()) j[key == "analysis" ? "analysis_settings" : key] = value;
  j["settings"] = {{"rays_per_face", model.radiation.rays_per_face},
                   {"seed", model.radiation.seed},
                   {"sun_rays_per_face", settings.loads.sun_rays_per_face},
                   {"earth_rays_per_face", o.loads.earth_rays_per_face},
                   {"solar_reflections", o.loads.solar_reflections},
                   {"load_positions_per_orbit", model.analysis.steps_per_orbit},
                   {"time_tolerance_K", model.analysis.time_tolerance_K}};
  for (auto& [k, v] : extra.items()) j[k] = v;
  for (const auto& [original, merged] : model.node_map) j["node_map"][original] = merged;  // (compare reads it)
  if (!o.json_out.empty()) write_text_atomically(o.json_out, j.dump(1) + "\n", inputs);
  if (!o.plot_out.empty()) plot_png("temperatures", j, o.plot_out);
  if (!o.quiet) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!o.json_out.empty()) std::printf("wrote %s\n", o.json_out.c_str());
    if (!o.plot_out.empty()) std::printf("wrote %s\n", o.plot_out.c_str());
    std::printf("simulate: done in %.1f s (environment %s, analysis %s)\n", seconds,
                model.environment.type == EnvironmentType::orbit ? "orbit" : "fixed_sun",
                model.analysis.type == AnalysisType::steady ? "steady" : "transient_orbit");
  }
}

}  // namespace

void add_simulate(CLI::App& app) {
  auto opts = std::make_shared<SimulateOptions>();
  auto* sub = app.add_subcommand(
      "simulate",
      "thermal simulation of MODEL in its environment (steady, or transient over one orbit until "
      "orbit-periodic): radiative couplings, solar/albedo/Earth-IR loads with self-shadowing, "
      "temperatures per node (docs/thermal.md)");
  sub->add_option("MODEL", opts->model, "model.json or mesh")->required();
  sub->add_option("--json", opts->json_out, "write the result JSON here");
  sub->add_option("--vtk", opts->vtk_dir,
                  "write a ParaView series into this folder: one .vtu per time step (per-face node, material, "
                  "temperature K, absorbed flux W/m^2) and MODEL.pvd (docs/exchange.md)");
  sub->add_option("--plot", opts->plot_out, "write a PNG of every node's temperature over the orbit");
  sub->add_flag("--noise-floor", opts->noise_floor,
                "run with several seeds (--noise-runs) and report the max |dT| over every pair of runs, the median pair and the run time");
  sub->add_option("--noise-runs", opts->noise_runs, "runs for --noise-floor")->check(CLI::Range(2, 100));
  sub->add_option("--noise-target", opts->noise.target_K,
                  "noise-targeted sampling: nodes whose estimated Monte Carlo temperature standard error exceeds "
                  "this get more samples (IR rays and sun/Earth samples separately) [K]; the largest seed-to-seed "
                  "|dT| (--noise-floor) is ~3-4x it (0 = off; boosts in the model file are kept)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e3));
  sub->add_option("--noise-budget", opts->noise.budget,
                  "noise-targeted sampling: at most this many extra IR rays, and extra sun/Earth samples, as a "
                  "multiple of the model's totals (the target is raised until the boosts fit)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e3));
  sub->add_option("--noise-max-samples", opts->noise.max_samples,
                  "noise-targeted sampling: at most this many extra IR rays, and extra sun/Earth samples, in all")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e15));
  sub->add_option("--rays,--rays-per-face", opts->rays_per_face, "IR view-factor rays per face side (default: the model's)")
      ->check(CLI::PositiveNumber);
  sub->add_option_function<int>(
         "--sun-rays", [opts](int n) { opts->loads.sun_rays_per_face = n; opts->sun_rays_set = true; },
         "shadow samples per face side (default 256; bare meshes: sized by face count)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--raw-mesh", opts->raw_mesh,
                "bare mesh: skip the cleanup (duplicates, open sheets two-sided, touching faces) and the "
                "size-aware ray budgets");
  sub->add_option("--earth-rays", opts->loads.earth_rays_per_face, "Earth view rays per face side")
      ->check(CLI::PositiveNumber)->capture_default_str();
  sub->add_flag("!--no-reflections", opts->loads.solar_reflections, "skip solar-band reflections between faces");
  sub->add_option("--seed", opts->seed,
                  "Monte Carlo seed of rays and sun/Earth samples (default: the model's radiation.seed); "
                  "another seed gives an independent draw of the same model")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--load-positions", opts->load_positions,
                  "orbit positions where loads are ray traced (default: the model's analysis.steps_per_orbit)")
      ->check(CLI::Range(4, 1000000));
  sub->add_option("--time-tolerance", opts->time_tolerance_K,
                  "target of the estimated time-discretization error of an orbit transient [K] (default: the "
                  "model's analysis.time_tolerance_K, 0.01)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("-q,--quiet", opts->quiet, "no progress or table");
  sub->callback([opts] { run_guarded([opts] { run_simulate(*opts); }); });
}

}  // namespace thermodec::cli
