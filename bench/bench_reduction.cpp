// Reduction trials: incremental (reused rays, correlated sampling) vs naive (everything
// recomputed) on the sample satellite, one line per case, ratio measured in this run. By
// default one trial per node (every node once, as the first step of a sensitivity sweep), so
// the total is representative of a sweep, not of a chosen node. Also prints the trial noise
// floor (each node's samples redrawn in turn).
//   bench_reduction [MODEL] [trials (default: number of nodes)] [--sweep] [--no-trial-noise] [--incremental-only]
//                   [--reduce-sampling] [--gaps] [--candidate REPORT.json]
//                   [--dump-pair REPORT.json NODE RATIO DIR]
// --candidate times one combined candidate instead: every node at the ratio a `reduce` report
// asked for (its nodes' "requested_ratio", decimated under its "max_relative_area_change"), incremental
// against the reference and then simulated from scratch, with the incremental trial's phases.
// --dump-pair writes that candidate (under the report's per-node area bounds too) and the same
// with NODE at RATIO, both simulated from scratch, as DIR/a.json and DIR/b.json with their max
// |dT| printed: the two models to compare with `simulate --json`, `viewfactors --json` and
// bench/node_difference_sources.py (what one step of one node moves, and through what).
// --reduce-sampling first multiplies the noisy nodes' samples as `reduce` does (its noise
// target, decide_sampling_boosts), so the trials cost what they cost inside `reduce`.
// MODEL is a model.json or a bare mesh; a bare mesh gets `reduce`'s size-aware ray budgets
// (apply_bare_mesh_reduction_budget), not its noise-targeted boosts.
// --sweep also runs the whole sensitivity sweep of `reduce` (every node, its ratios, cap 1 K),
// serially, each trial incremental and then simulated from scratch right after it. Its first
// ratio includes the trials whose candidate mesh an earlier one had (answered from the
// reference's cache, as a real sweep meets them; the naive path simulates them again); the
// second leaves them out: the trials evaluated both ways, the like-for-like ratio.
#include <chrono>
#include <ctime>
#include <optional>
#include <cstdio>
#include <algorithm>
#include <string>
#include <vector>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "thermodec/nodes/load_model.h"
#include "thermodec/reduction/reduce_model.h"
#include "thermodec/reduction/reduction_reference.h"
#include "thermodec/reduction/sensitivity.h"
#include "thermodec/thermal/simulate_model.h"

using namespace thermodec;
using Clock = std::chrono::steady_clock;

// --candidate: the ratios a reduce report asked of each node of `model` and its area bound.
struct ReportCandidate {
  Eigen::VectorXd ratios;
  double max_relative_area_change = 0.0;
  int reduced = 0;
};
static ReportCandidate read_candidate(const std::string& report_path, const ThermalModel& model) {
  std::ifstream in(report_path);
  if (!in) throw std::runtime_error("cannot open it");
  const nlohmann::json report = nlohmann::json::parse(in);
  ReportCandidate c;
  c.max_relative_area_change = report.at("max_relative_area_change").get<double>();
  c.ratios = Eigen::VectorXd::Zero(static_cast<int>(model.nodes.size()));
  for (std::size_t k = 0; k < model.nodes.size(); ++k) {
    const auto it = report.at("nodes").find(model.nodes[k].name);
    if (it != report.at("nodes").end()) c.ratios[k] = it->at("requested_ratio").get<double>();
    c.reduced += c.ratios[k] > 0.0;
  }
  return c;
}

// --dump-pair REPORT NODE RATIO DIR: the report's candidate (its per-node area bounds too) and the
// same with NODE at RATIO, both simulated from scratch, written as DIR/a.json and DIR/b.json.
static int dump_pair(ReductionReference& ref, const ReportCandidate& c, const std::string& report_path,
                     const std::string& node, double ratio, const std::string& dir) {
  std::ifstream in(report_path);
  const nlohmann::json report = nlohmann::json::parse(in);
  DecimationOptions dec = ref.decimation_options();
  dec.max_relative_area_change = c.max_relative_area_change;
  if (report.contains("node_max_relative_area_change"))
    dec.node_max_relative_area_change = report.at("node_max_relative_area_change").get<std::vector<double>>();
  if (dec.reflection_cap > 0.0) dec.reflection = ref.reflection();  // as reduce_model (one case)
  ref.set_decimation_options(dec);
  Eigen::VectorXd rb = c.ratios;
  int k = -1;
  for (std::size_t i = 0; i < ref.model().nodes.size(); ++i)
    if (ref.model().nodes[i].name == node) k = static_cast<int>(i);
  if (k < 0) return 1;
  rb[k] = ratio;
  for (int pass = 0; pass < 2; ++pass) {
    const Candidate cand = ref.candidate(pass == 0 ? c.ratios : rb, true);
    std::printf("%s: %d faces, max|dT| %.4f K at %s\n", pass == 0 ? "a" : "b", cand.model.mesh.num_faces(),
                cand.difference.max_abs_K, cand.difference.node.c_str());
    const std::string nm = pass == 0 ? "a" : "b";
    save_model(cand.model, dir + "/" + nm + ".json", dir + "/" + nm + ".obj");
  }
  return 0;
}

// --candidate: that candidate, incremental against the reference, then from scratch.
static int time_candidate(ReductionReference& ref, const ReportCandidate& c, const std::string& report_path) {
  DecimationOptions dec = ref.decimation_options();
  dec.max_relative_area_change = c.max_relative_area_change;
  ref.set_decimation_options(dec);
  auto t0 = Clock::now();
  const TrialResult a = ref.trial(c.ratios);
  const double ti = std::chrono::duration<double>(Clock::now() - t0).count();
  t0 = Clock::now();
  const TrialResult b = ref.verify(c.ratios);
  const double tf = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("candidate of %s: %d nodes reduced, %d faces\n", report_path.c_str(), c.reduced, a.faces_after);
  std::printf("incremental: max|dT| %.4f K in %.2f s (decimation %.2f s, couplings %.2f s, loads %.2f s, solve %.2f s; "
              "couplings and loads overlap)\n",
              a.max_abs_dT_K, ti, a.timing.decimation_s, a.timing.couplings_s, a.timing.loads_s, a.timing.solve_s);
  std::printf("from scratch: max|dT| %.4f K in %.2f s: incremental %.2fx faster\n", b.max_abs_dT_K, tf, tf / ti);
  return 0;
}

int main(int argc, char** argv) {
  std::vector<std::string> args;
  std::string candidate_report, dump_node, dump_dir;
  double dump_ratio = 0.0;
  bool sweep = false, trial_noise = true, incremental_only = false, reduce_sampling = false, show_gaps = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--sweep") sweep = true;
    else if (a == "--no-trial-noise") trial_noise = false;
    else if (a == "--incremental-only") incremental_only = true;  // for profilers: no naive trials
    else if (a == "--reduce-sampling") reduce_sampling = true;
    else if (a == "--gaps") show_gaps = true;
    else if (a == "--candidate" && i + 1 < argc) candidate_report = argv[++i];
    else if (a == "--dump-pair" && i + 4 < argc) {
      candidate_report = argv[++i];
      dump_node = argv[++i];
      dump_ratio = std::stod(argv[++i]);
      dump_dir = argv[++i];
    }
    else args.push_back(a);
  }
  const std::string path = args.size() > 0 ? args[0] : THERMODEC_SOURCE_DIR "/sample_models/satellite/model.json";
  ThermalModel model = load_model(path);
  ReduceSettings settings;
  apply_bare_mesh_reduction_budget(model, settings);  // no-op for a model.json
  if (reduce_sampling && !has_sampling_boosts(model)) {
    // What `reduce` traces: the noisy nodes' samples multiplied for its noise target.
    const SamplingBoosts b = decide_sampling_boosts(model, settings.reference.simulation,
                                                    settings.noise_target_fraction * settings.tolerance_K);
    for (std::size_t k = 0; k < b.boost.size(); ++k) model.nodes[k].sampling_boost = b.boost[k];
    std::printf("%s\n", b.describe(model.nodes).c_str());
  }
  ReportCandidate candidate;
  if (!candidate_report.empty()) {  // read before the reference: a bad report fails at once
    try {
      candidate = read_candidate(candidate_report, model);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_reduction: %s is not a reduce report.json: %s\n", candidate_report.c_str(), e.what());
      return 1;
    }
  }
  const int n = static_cast<int>(model.nodes.size());
  const int trials = args.size() > 1 ? std::stoi(args[1]) : n;
  auto t0 = Clock::now();
  ReductionReference ref(model, settings.reference);
  const double t_ref = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("%s: %d faces, %d nodes; reference simulation + reusable state %.2f s\n", path.c_str(),
              model.mesh.num_faces(), n, t_ref);
  if (!dump_node.empty()) return dump_pair(ref, candidate, candidate_report, dump_node, dump_ratio, dump_dir);
  if (!candidate_report.empty()) return time_candidate(ref, candidate, candidate_report);
  if (trial_noise) {
    t0 = Clock::now();
    const TrialNoiseFloor tn = ref.trial_noise_floor();
    std::printf("trial noise floor (one node's samples redrawn at a time): max |dT| %.4f K (node %s redrawn, at %s, t = %.0f s) in %.2f s\n",
                tn.worst.max_abs_K, model.nodes[tn.worst_resampled_node].name.c_str(), tn.worst.node.c_str(),
                tn.worst.time_s, std::chrono::duration<double>(Clock::now() - t0).count());
    for (int k = 0; k < n; ++k) std::printf("  %-12s %.4f K\n", model.nodes[k].name.c_str(), tn.node_max_abs_dT_K[k]);
  }
  // CPU time (all threads) as well as wall time: on a shared machine the wall ratio moves with
  // the load of other processes, the CPU (work) ratio does not.
  // Fewer trials than nodes: the nodes with the most faces first (the costliest trials, and
  // the ones a reduction is about; 2-face CAD nodes would be answered by the reference).
  std::vector<int> order(n);
  for (int k = 0; k < n; ++k) order[k] = k;
  if (trials < n)
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return ref.faces_per_node()[a] > ref.faces_per_node()[b]; });
  double inc_s = 0.0, full_s = 0.0, inc_cpu = 0.0, full_cpu = 0.0, max_gap = 0.0;
  TrialResult::Timing phases;  // incremental trials, summed
  for (int i = 0; i < trials; ++i) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
    r[order[i % n]] = 0.5 + 0.07 * (i % 5);  // a different single node each case
    t0 = Clock::now();
    std::clock_t c0 = std::clock();
    const TrialResult a = ref.trial(r);
    phases.decimation_s += a.timing.decimation_s;
    phases.couplings_s += a.timing.couplings_s;
    phases.loads_s += a.timing.loads_s;
    phases.solve_s += a.timing.solve_s;
    const double ti = std::chrono::duration<double>(Clock::now() - t0).count();
    inc_cpu += double(std::clock() - c0) / CLOCKS_PER_SEC;
    t0 = Clock::now();
    c0 = std::clock();
    const TrialResult b = incremental_only ? a : ref.verify(r);
    const double tf = std::chrono::duration<double>(Clock::now() - t0).count();
    full_cpu += double(std::clock() - c0) / CLOCKS_PER_SEC;
    inc_s += ti;
    full_s += tf;
    max_gap = std::max(max_gap, std::abs(a.max_abs_dT_K - b.max_abs_dT_K));
    std::printf("node %-12s ratio %.2f: %4d faces, max|dT| %.4f K incremental in %6.3f s (couplings %.3f, loads %.3f) | naive %.4f K in %6.3f s | %.1fx\n",
                model.nodes[order[i % n]].name.c_str(), r.maxCoeff(), a.faces_after, a.max_abs_dT_K, ti,
                a.timing.couplings_s, a.timing.loads_s, b.max_abs_dT_K, tf, tf / ti);
  }
  std::printf("incremental vs naive: %.2f s vs %.2f s over %d trials = %.1fx faster; max |dT| gap %.2e K\n", inc_s,
              full_s, trials, full_s / inc_s, max_gap);
  std::printf("incremental trials, wall time per phase (sum over %d trials): decimation %.3f s, couplings %.3f s, "
              "loads %.3f s, solve %.3f s\n",
              trials, phases.decimation_s, phases.couplings_s, phases.loads_s, phases.solve_s);
  std::printf("incremental vs naive, CPU time of all threads: %.2f s vs %.2f s = %.1fx less work\n", inc_cpu, full_cpu,
              full_cpu / inc_cpu);
  if (sweep) {
    // The whole sensitivity sweep of `reduce` (serial, each trial using both cores), every
    // trial evaluated incrementally and then naively right after it, with fresh references (so
    // that neither finds the other's, or the trials above', results cached). Side by side, a
    // change in the machine's speed during the run (other guests on this host) moves both
    // alike; run one after the other, the ratio moved by +-0.5x. Both should give the same
    // results, so the sweep takes the path either would alone (it follows the incremental one);
    // the largest gap is printed, and with --gaps every trial whose gap exceeds 1e-8 K.
    SensitivityOptions so = settings.sensitivity;  // (the coarse sweep on big bare meshes)
    so.parallel = false;
    const ReductionReference inc_ref(model, settings.reference);
    std::optional<ReductionReference> full_ref;
    if (!incremental_only) full_ref.emplace(model, settings.reference);
    double wall[2] = {0.0, 0.0}, cpu[2] = {0.0, 0.0}, gap = 0.0;
    // The same sums over the trials the incremental path actually evaluated: a ratio whose
    // candidate mesh an earlier trial already had (e.g. 0.96 and 0.98 of a 60-face panel, both
    // 2 faces) is answered from the reference's cache after decimating, which the naive path
    // does not do.
    double evaluated_wall[2] = {0.0, 0.0}, evaluated_cpu[2] = {0.0, 0.0};
    int calls = 0;
    TrialResult::Timing sweep_phases;  // incremental trials actually evaluated (not cached)
    const TrialFunction trial = [&](const Eigen::VectorXd& r) {
      const int before = inc_ref.trials_evaluated();
      auto w0 = Clock::now();
      std::clock_t c0 = std::clock();
      TrialResult a = inc_ref.trial(r);
      const double wi = std::chrono::duration<double>(Clock::now() - w0).count(), ci = double(std::clock() - c0) / CLOCKS_PER_SEC;
      wall[0] += wi;
      cpu[0] += ci;
      ++calls;
      const bool evaluated = inc_ref.trials_evaluated() > before;
      if (evaluated) {
        evaluated_wall[0] += wi;
        evaluated_cpu[0] += ci;
      }
      if (inc_ref.trials_evaluated() > before) {
        sweep_phases.decimation_s += a.timing.decimation_s;
        sweep_phases.couplings_s += a.timing.couplings_s;
        sweep_phases.loads_s += a.timing.loads_s;
        sweep_phases.solve_s += a.timing.solve_s;
      }
      if (full_ref) {
        w0 = Clock::now();
        c0 = std::clock();
        const TrialResult b = full_ref->verify(r);
        const double w = std::chrono::duration<double>(Clock::now() - w0).count(), c = double(std::clock() - c0) / CLOCKS_PER_SEC;
        wall[1] += w;
        cpu[1] += c;
        if (evaluated) {
          evaluated_wall[1] += w;
          evaluated_cpu[1] += c;
        }
        gap = std::max(gap, std::abs(a.max_abs_dT_K - b.max_abs_dT_K));
        if (show_gaps && std::abs(a.max_abs_dT_K - b.max_abs_dT_K) > 1e-8) {
          Eigen::Index node;
          r.maxCoeff(&node);
          std::printf("gap %.3e K: node %s ratio %.3f, %d faces: incremental %.6f K, naive %.6f K\n",
                      std::abs(a.max_abs_dT_K - b.max_abs_dT_K), model.nodes[node].name.c_str(), r[node], a.faces_after,
                      a.max_abs_dT_K, b.max_abs_dT_K);
        }
      }
      return a;
    };
    sensitivity_analysis(n, trial, so);
    const int count = inc_ref.trials_evaluated();
    std::printf("sweep, incremental trials, wall time per phase: decimation %.2f s, couplings %.2f s, loads %.2f s, solve %.2f s\n",
                sweep_phases.decimation_s, sweep_phases.couplings_s, sweep_phases.loads_s, sweep_phases.solve_s);
    if (incremental_only)
      std::printf("whole sensitivity sweep (%d trials, %d evaluated, serial): incremental %.2f s, CPU %.2f s\n", calls, count,
                  wall[0], cpu[0]);
    else
      std::printf("whole sensitivity sweep (%d trials, serial, each incremental then naive): incremental %.2f s vs naive %.2f s = "
                  "%.1fx faster; CPU %.2f s vs %.2f s = %.1fx; max |dT| gap %.2e K\n",
                  calls, wall[0], wall[1], wall[1] / wall[0], cpu[0], cpu[1], cpu[1] / cpu[0], gap);
    if (!incremental_only && evaluated_cpu[0] > 0.0)
      std::printf("  of its %d trials, %d answered from the cache of candidate meshes (same mesh as an earlier trial);\n"
                  "  over the %d evaluated both ways: %.2f s vs %.2f s = %.1fx faster; CPU %.2f s vs %.2f s = %.1fx\n",
                  calls, calls - count, count, evaluated_wall[0], evaluated_wall[1], evaluated_wall[1] / evaluated_wall[0],
                  evaluated_cpu[0], evaluated_cpu[1], evaluated_cpu[1] / evaluated_cpu[0]);
  }
  return 0;
}
