// `thermodec reduce MODEL --tolerance K [--strategy informed|uniform] [--case FILE ...] --out DIR`
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include "commands.h"
#include "thermodec/common/errors.h"
#include "thermodec/common/peak_memory.h"
#include "thermodec/nodes/load_case.h"
#include "thermodec/common/output_paths.h"
#include "thermodec/common/staged_folder.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/reduction/merge_reduction.h"
#include "thermodec/reduction/record_budget.h"
#include "thermodec/reduction/reduce_model.h"
#include "thermodec/report/reduction_report.h"
#include "thermodec/thermal/simulate_model.h"
#ifdef THERMODEC_HAS_MPI
#include "thermodec/reduction/mpi_sweep.h"
#endif

namespace thermodec::cli {
namespace {

struct ReduceCliOptions {
  std::string model;
  std::string out_dir;
  double tolerance_K = 0.5;
  std::string strategy = "informed";
  std::string prediction = "per-node";
  int rays_per_face = 0;
  double cap_factor = 2.0;
  int max_evaluations = InformedOptions{}.max_evaluations;
  bool no_plots = false;
  bool quiet = false;
  bool raw_mesh = false;
  bool max_evaluations_set = false;
  double noise_target_fraction = 0.05;
  bool no_thinning = false;
  double max_area_change = -1.0;  // < 0: the default
  bool global_area_bound = false;
  double record_memory_GiB = 0.0;  // 0: the default (record_budget.h)
  std::vector<std::string> case_files;
  std::vector<double> prediction_targets;  // empty: the default (ReduceSettings, budgets)
  std::string collapse_cost = "radiative";  // as reduction_decimation_options()
  double max_normal_deviation_deg = reduction_decimation_options().max_normal_deviation_deg;
  double max_contour_deviation = reduction_decimation_options().max_contour_deviation;
  double projected_area_budget = reduction_decimation_options().projected_area_budget;
  double max_fold_deg = reduction_decimation_options().max_fold_deg;
  double projected_area_cap = reduction_decimation_options().projected_area_cap;
  double reflection_cap = reduction_decimation_options().reflection_cap;
  bool fixed_node_areas = !reduction_decimation_options().restore_node_areas;
  double max_kinked_contour_deviation = reduction_decimation_options().max_kinked_contour_deviation;
  double wide_kink_area_fraction = reduction_decimation_options().wide_kink_area_fraction;
  double wide_kink_part_fraction = reduction_decimation_options().wide_kink_part_fraction;
  bool conforming_contacts = !reduction_decimation_options().release_contacts;
  double near_contact_fraction = reduction_decimation_options().near_contact_fraction;
  bool merge_nodes = false;      // reduction/merge_reduction.h
  NodeMergeSettings merge;
};

// What `reduce` writes into its folder (report/reduction_report.h); only these may be there.
const std::vector<std::string> kReduceOutputs = {"model.json", "reduced.obj", "report.json", "sensitivity.png",
                                                 "predicted_vs_real.png", "temperatures.png", "mesh.png"};

// Under an MPI launcher: every rank runs the reduction up to the end of the sensitivity sweep,
// rank 0 alone goes on, speaks and writes (reduction/mpi_sweep.h).
struct Ranks {
  int rank = 0, size = 1;
#ifdef THERMODEC_HAS_MPI
  Ranks() {
    const MpiWorld w = start_mpi();
    rank = w.rank;
    size = w.size;
  }
  ~Ranks() { finish_mpi(); }
#endif
};

void run_reduce(const ReduceCliOptions& o) {
  const Ranks ranks{};
  const bool root = ranks.rank == 0;
  ModelLoadOptions load = model_load_options();
  load.clean_bare_mesh = !o.raw_mesh;
  ThermalModel model = load_model(o.model, load);
  // Every input is protected from the outputs, and the folder is checked before the work.
  std::vector<std::filesystem::path> inputs{o.model, model.mesh_path};
  for (const auto& f : o.case_files) inputs.push_back(f);
  check_output_folder(o.out_dir, kReduceOutputs, inputs);
  nodes_matching(model, o.merge.keep);  // a --keep-node that matches nothing: refused before any work
  // The result is written into a staging folder beside --out and swapped into place once
  // complete; the lock refuses a second run into the same folder (common/staged_folder.h).
  std::optional<StagedFolder> staged;
  if (root) staged.emplace(o.out_dir);
  ReduceSettings s;
  s.informed.max_evaluations = o.max_evaluations;
  apply_bare_mesh_reduction_budget(model, s);
  apply_large_model_sweep(model, s);
  if (o.max_evaluations_set) s.informed.max_evaluations = o.max_evaluations;
  if (!o.prediction_targets.empty()) s.prediction_targets = o.prediction_targets;
  if (model.mesh_cleanup && root) std::cout << "bare mesh cleanup:\n" << model.mesh_cleanup->summary();
  if (o.rays_per_face > 0) model.radiation.rays_per_face = o.rays_per_face;
  s.tolerance_K = o.tolerance_K;
  s.strategy = o.strategy == "uniform" ? ReductionStrategy::uniform : ReductionStrategy::informed;
  s.informed.start_by_superposition = o.prediction == "superposition";
  s.sensitivity_cap_factor = o.cap_factor;
  s.noise_target_fraction = o.noise_target_fraction;
  s.thin_oversampling = !o.no_thinning;
  s.per_node_area_bound = !o.global_area_bound;
  if (o.max_area_change >= 0.0) {  // as given: not lowered from the tolerance
    s.reference.decimation.max_relative_area_change = o.max_area_change;
    s.area_error_fraction = 0.0;
  }
  s.reference.decimation.collapse_cost =
      o.collapse_cost == "radiative" ? CollapseCostKind::radiative : CollapseCostKind::geometric;
  s.reference.decimation.max_normal_deviation_deg = o.max_normal_deviation_deg;
  s.reference.decimation.max_contour_deviation = o.max_contour_deviation;
  s.reference.decimation.projected_area_budget = o.projected_area_budget;
  s.reference.decimation.max_fold_deg = o.max_fold_deg;
  s.reference.decimation.projected_area_cap = o.projected_area_cap;
  s.reference.decimation.reflection_cap = o.reflection_cap;
  s.reference.decimation.restore_node_areas = !o.fixed_node_areas;
  s.reference.decimation.max_kinked_contour_deviation = o.max_kinked_contour_deviation;
  s.reference.decimation.wide_kink_area_fraction = o.wide_kink_area_fraction;
  s.reference.decimation.wide_kink_part_fraction = o.wide_kink_part_fraction;
  s.reference.decimation.release_contacts = !o.conforming_contacts;
  s.reference.decimation.near_contact_fraction = o.near_contact_fraction;
  if (o.record_memory_GiB > 0.0) s.reference.record_budget_bytes = static_cast<std::size_t>(o.record_memory_GiB * 1073741824.0);
  // Load cases read (and checked) before any simulation.
  for (const auto& f : o.case_files) s.extra_cases.push_back(load_case(f, model));
#ifdef THERMODEC_HAS_MPI
  if (ranks.size > 1) s.sweep = mpi_sweep({ranks.rank, ranks.size});
#endif
  if (!o.quiet && root) {
    // Elapsed wall time on every line: on CAD meshes a reduction runs for an hour.
    const auto start = std::chrono::steady_clock::now();
    s.progress = [start](const std::string& m) {
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      char stamp[32];
      std::snprintf(stamp, sizeof stamp, "[%7.1f s] ", t);
      std::cerr << "reduce: " << stamp << m << "\n";
    };
  }
  if (root) std::cerr << "reduce: " << o.model << ": " << model.mesh.num_faces() << " faces, " << model.nodes.size()
            << " nodes, " << model.radiation.rays_per_face << " IR rays and "
            << s.reference.simulation.loads.sun_rays_per_face << " sun samples per face side, tolerance " << o.tolerance_K << " K, strategy " << o.strategy
            << (s.extra_cases.empty() ? std::string() : ", " + std::to_string(1 + s.extra_cases.size()) + " load cases")
            << (ranks.size > 1 ? ", sensitivity sweep over " + std::to_string(ranks.size) + " MPI ranks" : std::string())
            << (o.merge_nodes ? ", merging nodes" : "")
            << "\n";
  guard_simulation_cost("reduce", check_simulation_cost(model, s.reference.simulation, s.extra_cases), o.quiet || !root);
  ReductionRun run = o.merge_nodes ? reduce_with_node_merging(model, s, o.merge) : reduce_model(model, s);
  if (run.sweep_only) return;  // an MPI rank other than 0: its curves went to rank 0
  run.ranks = ranks.size;
  run.peak_memory_bytes = peak_resident_memory_bytes();
  const auto missing = write_reduction_outputs(run, staged->staging(), inputs, !o.no_plots);
  if (!missing.empty()) {
    std::string list;
    for (const auto& w : missing) list += (list.empty() ? "" : "; ") + w;
    throw IOError("the result could not be written completely, " + o.out_dir + " keeps its previous content (plot not written: " +
                  list + "); free space or pass --no-plots");
  }
  check_output_folder(o.out_dir, kReduceOutputs, inputs);  // nothing foreign came in meanwhile
  staged->commit();
  std::cout << reduction_summary(run);
  char mem[160];
  const std::size_t records = record_budget_bytes(s.reference.record_budget_bytes);
  std::snprintf(mem, sizeof mem, "peak memory: %.0f MiB (ray records allowed up to %.2f GiB)", run.peak_memory_bytes / 1048576.0,
                records / 1073741824.0);
  std::cout << mem;
  if (run.ranks > 1) {
    std::snprintf(mem, sizeof mem, " (rank 0; largest of the other %d ranks %.0f MiB)", run.ranks - 1,
                  run.peak_memory_bytes_other_ranks / 1048576.0);
    std::cout << mem;
  }
  std::cout << "\n";
  std::cout << "results: " << o.out_dir << " (model.json, reduced.obj, report.json"
            << (o.no_plots ? "" : ", *.png") << ")\n";
}

}  // namespace

void add_reduce(CLI::App& app) {
  auto o = std::make_shared<ReduceCliOptions>();
  auto* sub = app.add_subcommand(
      "reduce",
      "reduce MODEL's mesh as far as a temperature tolerance allows, node by node, and verify.\n"
      "informed (default): a sensitivity sweep per node predicts each node's ratio; the combined\n"
      "model is simulated, the nodes that contribute most to any excess are backed off and spare\n"
      "tolerance is used to push nodes further. uniform: one ratio for all nodes (paper §IV).\n"
      "The result always passed a full re-simulation: max |dT| over all nodes and the orbit <= K.");
  sub->add_option("MODEL", o->model, "model.json or bare mesh (.obj .ply .stl)")->required()->check(CLI::ExistingFile);
  sub->add_option("-t,--tolerance", o->tolerance_K,
                  "max temperature difference allowed vs the unreduced model [K]; must be at least "
                  "twice the measured Monte Carlo noise floor")
      ->capture_default_str();
  sub->add_option("-s,--strategy", o->strategy, "informed | uniform")
      ->check(CLI::IsMember({"informed", "uniform"}))
      ->capture_default_str();
  sub->add_option("--prediction", o->prediction,
                  "informed: the first candidate. per-node: each node's largest ratio whose own sweep stays "
                  "within the tolerance (paper). superposition: the ratios whose summed single-node "
                  "difference fields stay within it, corrected by the measured/predicted ratio; the history "
                  "in report.json lists the superposition's prediction beside every measured candidate")
      ->check(CLI::IsMember({"per-node", "superposition"}))
      ->capture_default_str();
  sub->add_option("--prediction-targets", o->prediction_targets,
                  "informed: the predicted-vs-real plot's targets, as multiples of the search tolerance, comma "
                  "separated; each but 1 costs a trial of a combined candidate (default 0.1,0.25,0.5,1,2; 1 alone "
                  "for models over 2000 faces, where such a trial is about a whole simulation)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  sub->add_option("-o,--output,--out", o->out_dir, "output folder (model.json, reduced.obj, report.json, plots)")->required();
  sub->add_option("--rays,--rays-per-face", o->rays_per_face, "IR view-factor rays per face side (default: the model's)");
  sub->add_option("--sensitivity-cap", o->cap_factor,
                  "a node's sweep stops once max |dT| exceeds this multiple of the tolerance")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option_function<int>(
         "--max-evaluations", [o](int n) { o->max_evaluations = n; o->max_evaluations_set = true; },
         "bound on trials after the prediction (default 80; 40 for model files and 20 for bare meshes over 2000 faces)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--noise-target", o->noise_target_fraction,
                  "noise-targeted sampling: nodes whose estimated Monte Carlo temperature noise exceeds this "
                  "fraction of the tolerance get more samples (0 = off; boosts already in the model file are kept); "
                  "a model whose every node lies far under it is thinned: its IR rays or sun/Earth samples divided "
                  "by a common power of two (4 to 64) in every simulation of the reduction and in the reduced model")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_flag("--no-thinning", o->no_thinning,
                "noise-targeted sampling only adds samples: an oversampled model keeps its sample counts");
  sub->add_option("--max-area-change", o->max_area_change,
                  "bound on each node's relative area change by the decimator, used as given (default: from the "
                  "tolerance, so that area drift costs at most 10 % of it, per node from the reference's network)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--global-area-bound", o->global_area_bound,
                "one area bound for every node, dT = T dA/4A at the hottest node, instead of each node's own "
                "first-order sensitivity to its area (docs/reduction.md)");
  sub->add_option("--collapse-cost", o->collapse_cost,
                  "ranking of the decimator's collapses: geometric (Lindstrom-Turk volume and shape) or radiative "
                  "(also each node's projected area over all directions; docs/decimation.md)")
      ->check(CLI::IsMember({"geometric", "radiative"}))
      ->capture_default_str();
  sub->add_option("--max-normal-deviation", o->max_normal_deviation_deg,
                  "the decimator refuses a collapse that turns a face by more than this [degrees]; CAD meshes of "
                  "long thin triangles reach further with a wider bound (docs/decimation.md, \"Reach\")")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 179.0));
  sub->add_option("--projected-area-budget", o->projected_area_budget,
                  "faces may turn past --max-normal-deviation (up to --max-fold) while the summed change of their "
                  "area vectors stays within this multiple of the area bound times the node's area (a bound on its "
                  "projected-area change in every direction; 0 = per-face check only; docs/decimation.md)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--max-fold", o->max_fold_deg,
                  "no face turns by more than this [degrees], whatever its area (with --projected-area-budget)")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 179.0));
  sub->add_option("--projected-area-cap", o->projected_area_cap,
                  "the decimator keeps each node's projected area in 64 directions within this multiple of the "
                  "node's area bound times its area of its input; the budget then no longer refuses (0 = off: the "
                  "budget alone; docs/decimation.md, \"Projected-area cap\")")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--reflection-cap", o->reflection_cap,
                  "the decimator moves the sunlight reflected onto each node (lit faces merged with dark ones) by "
                  "at most this multiple of the node's area bound times the power it absorbs (0 = off; "
                  "docs/decimation.md, \"Reflected-sunlight cap\")")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--fixed-node-areas", o->fixed_node_areas,
               "no node-area restoration: a collapse past a node's area bound is refused, not restored by offsets "
               "of the node's free vertices (docs/decimation.md, \"Node-area restoration\")");
  sub->add_flag("--conforming-contacts", o->conforming_contacts,
               "the decimator keeps every contact vertex (a sheet standing on a panel, a part touching a flat "
               "face at a point) in the flat region too, so the output stays conforming there (default: the "
               "flat region drops them; docs/decimation.md, \"Released contacts\")");
  sub->add_option("--near-contact", o->near_contact_fraction,
                  "freeze a vertex lying within this fraction of its shortest edge of a nearly parallel face of another "
                  "node (a hinge end in the plane of its wall, a bracket millimetres off a panel): the exchange across such a gap "
                  "is decided at the gap's scale (0 = off; docs/decimation.md, \"Near contacts\")")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--max-kink", o->max_kinked_contour_deviation,
                  "with --projected-area-budget: a contour vertex up to this deviation (relative to the new segment) "
                  "may go when its nodes pay the outline's swept area from the budget")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--wide-kink", o->wide_kink_area_fraction,
                  "with --projected-area-cap: a contour vertex past --max-kink may go when the outline's swept "
                  "triangle is at most this fraction of each node's area bound x its area (0 = off)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--wide-kink-part", o->wide_kink_part_fraction,
                  "with --wide-kink: only on parts whose area is at most this fraction of the node's area")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--contour-deviation", o->max_contour_deviation,
                  "max deviation of a removed interface or boundary vertex from the new segment, relative to its length")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--record-memory", o->record_memory_GiB,
                  "memory for the reference's reusable ray records [GiB]: 2/17 for Earth ray geometry, the rest "
                  "filled by need, IR records first (up to 3/4), then sun/Earth records; beyond it trials re-trace "
                  "instead (same results, slower); with --case, the cases' references share it equally. Default: 4.25 GiB "
                  "or a quarter of the machine's memory if less")
      ->check(CLI::Range(0.01, 1024.0));
  sub->add_option("--case", o->case_files,
                  "another load case the reduced model must also meet (repeatable): a JSON file "
                  "{\"name\": .., \"environment\": {..}, \"analysis\": {..}} read over the model's own "
                  "(e.g. a cold case on another day of the year); every trial takes the worst case")
      ->check(CLI::ExistingFile);
  auto* merge = sub->add_flag("--merge-nodes", o->merge_nodes,
                              "also merge thermal nodes (neighbours sharing an edge or exchanging strongly) into "
                              "isothermal nodes, then decimate the merged model; verified against the original "
                              "through the node map (docs/reduction.md, \"Merging nodes\")");
  sub->add_option("--keep-node", o->merge.keep,
                  "with --merge-nodes: a node never merged (repeatable; a shell pattern such as 'panel_*' is "
                  "fine; fixed-temperature nodes are never merged)")
      ->needs(merge);
  sub->add_option("--merge-share", o->merge.tolerance_share,
                  "with --merge-nodes: the share of the tolerance the merges may spend; each original node's "
                  "decimation gets what its own merge left")
      ->needs(merge)
      ->capture_default_str()
      ->check(CLI::Range(0.01, 0.99));
  sub->add_option("--merge-small-share", o->merge.small_node_share,
                  "with --merge-nodes: the share of the tolerance small nodes (the fewest-faced, holding 10 % "
                  "of the faces: their decimation gains little) may take from the merges; at most "
                  "--merge-share (the default) turns this off")
      ->needs(merge)
      ->capture_default_str()
      ->check(CLI::Range(0.01, 0.99));
  sub->add_flag("--merge-signed-budgets", o->merge.signed_budgets,
                "with --merge-nodes: a merged node's decimation may move a member towards its original "
                "temperature by its merge's |dT| plus the tolerance (off: either way by the tolerance less it)")
      ->needs(merge);
  sub->add_flag("--raw-mesh", o->raw_mesh,
                "bare mesh: skip the cleanup (duplicates, open sheets two-sided, touching faces) and the "
                "size-aware ray budgets");
  sub->add_flag("--no-plots", o->no_plots, "write JSON and meshes only");
  sub->add_flag("-q,--quiet", o->quiet, "no progress on stderr");
  sub->callback([o] { run_guarded([o] { run_reduce(*o); }); });
}

}  // namespace thermodec::cli
