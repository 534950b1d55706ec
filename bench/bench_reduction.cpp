// Reduction trials: incremental (reused rays, correlated sampling) vs naive (everything
// recomputed) on the sample satellite, one line per case, ratio measured in this run. By
// default one trial per node (every node once, as the first step of a sensitivity sweep), so
// the total is representative of a sweep, not of a chosen node. Also prints the trial noise
// floor (each node's samples redrawn in turn).
//   bench_reduction [MODEL] [trials (default: number of nodes)] [--sweep] [--no-trial-noise] [--incremental-only]
//                   [--reduce-sampling]
// --reduce-sampling first multiplies the noisy nodes' samples as `reduce` does (its noise
// target, decide_sampling_boosts), so the trials cost what they cost inside `reduce`.
// MODEL is a model.json or a bare mesh; a bare mesh gets `reduce`'s size-aware ray budgets
// (apply_bare_mesh_reduction_budget), not its noise-targeted boosts.
// --sweep also runs the whole sensitivity sweep of `reduce` (every node, its ratios, cap 1 K)
// twice, serially: with incremental trials, then with every trial simulated from scratch; the
// ratio includes the trials that change nothing (answered by the reference) as a real sweep
// meets them.
#include <chrono>
#include <ctime>
#include <mutex>
#include <cstdio>
#include <algorithm>
#include <string>
#include <vector>

#include "thermodec/nodes/load_model.h"
#include "thermodec/reduction/reduce_model.h"
#include "thermodec/reduction/reduction_reference.h"
#include "thermodec/reduction/sensitivity.h"
#include "thermodec/thermal/simulate_model.h"

using namespace thermodec;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  std::vector<std::string> args;
  bool sweep = false, trial_noise = true, incremental_only = false, reduce_sampling = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--sweep") sweep = true;
    else if (a == "--no-trial-noise") trial_noise = false;
    else if (a == "--incremental-only") incremental_only = true;  // for profilers: no naive trials
    else if (a == "--reduce-sampling") reduce_sampling = true;
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
  const int n = static_cast<int>(model.nodes.size());
  const int trials = args.size() > 1 ? std::stoi(args[1]) : n;
  auto t0 = Clock::now();
  const ReductionReference ref(model, settings.reference);
  const double t_ref = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("%s: %d faces, %d nodes; reference simulation + reusable state %.2f s\n", path.c_str(),
              model.mesh.num_faces(), n, t_ref);
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
    // Fresh references, so that neither sweep finds the other's (or the trials') results cached.
    SensitivityOptions so = settings.sensitivity;  // (the coarse sweep on big bare meshes)
    so.parallel = false;  // one trial at a time, each using both cores, as above
    double wall[2] = {0.0, 0.0}, cpu[2] = {0.0, 0.0};
    TrialResult::Timing sweep_phases[2];
    int count[2] = {0, 0};
    for (int full = 0; full < (incremental_only ? 1 : 2); ++full) {
      const ReductionReference sweep_ref(model, settings.reference);
      std::mutex m;
      const TrialFunction trial = [&](const Eigen::VectorXd& r) {
        TrialResult t = full ? sweep_ref.verify(r) : sweep_ref.trial(r);
        std::lock_guard<std::mutex> lock(m);
        sweep_phases[full].decimation_s += t.timing.decimation_s;
        sweep_phases[full].couplings_s += t.timing.couplings_s;
        sweep_phases[full].loads_s += t.timing.loads_s;
        sweep_phases[full].solve_s += t.timing.solve_s;
        sweep_phases[full].simulation_s += t.timing.simulation_s;
        return t;
      };
      t0 = Clock::now();
      const std::clock_t c0 = std::clock();
      sensitivity_analysis(n, trial, so);
      wall[full] = std::chrono::duration<double>(Clock::now() - t0).count();
      cpu[full] = double(std::clock() - c0) / CLOCKS_PER_SEC;
      count[full] = sweep_ref.trials_evaluated();
    }
    std::printf("sweep, incremental trials, wall time per phase: decimation %.2f s, couplings %.2f s, loads %.2f s, solve %.2f s\n",
                sweep_phases[0].decimation_s, sweep_phases[0].couplings_s, sweep_phases[0].loads_s, sweep_phases[0].solve_s);
    if (incremental_only)
      std::printf("whole sensitivity sweep (%d trials, serial): incremental %.2f s, CPU %.2f s\n", count[0], wall[0], cpu[0]);
    else
      std::printf("whole sensitivity sweep (%d trials, serial): incremental %.2f s vs naive %.2f s = %.1fx faster; CPU %.2f s vs %.2f s = %.1fx\n",
                  count[0], wall[0], wall[1], wall[1] / wall[0], cpu[0], cpu[1], cpu[1] / cpu[0]);
  }
  return 0;
}
