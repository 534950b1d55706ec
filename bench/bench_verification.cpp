// Tolerance guarantee, re-measured: for each tolerance, `reduce` (informed, or --uniform) on a
// model, the faces kept, the verification's estimate +- SE and upper bound, then the original
// and the reduced model each simulated with 8 fresh seeds (disjoint from the search's and the
// verification's), and max |dT| over nodes and times of the 8-seed means and of the worst of
// the 64 seed pairs; last, the 64 pairs as a user would check with `simulate --seed N` on both
// files (`simulate`'s defaults: the original gets noise-targeted boosts decided at its seed,
// target 0.0025 K, up to 32x; the reduced model keeps the boosts its model.json carries): the mean +- SE of the pairs' max |dT|, the worst pair and how many of
// the 64 are within the tolerance.
//   bench_verification [MODEL] [--uniform] [--tolerances 0.5,0.1,0.05]
// One line per tolerance; never a pass/fail.
#include <chrono>
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "thermodec/nodes/load_model.h"
#include "thermodec/reduction/reduce_model.h"
#include "thermodec/thermal/simulate_model.h"

using namespace thermodec;

int main(int argc, char** argv) {
  std::vector<std::string> args;
  std::vector<double> tolerances{0.5, 0.1, 0.05};
  bool uniform = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--uniform") uniform = true;
    else if (a == "--tolerances" && i + 1 < argc) {
      tolerances.clear();
      std::stringstream ss(argv[++i]);
      for (std::string t; std::getline(ss, t, ',');) tolerances.push_back(std::stod(t));
    } else args.push_back(a);
  }
  const std::string path = args.empty() ? THERMODEC_SOURCE_DIR "/sample_models/satellite/model.json" : args[0];
  const ThermalModel model = load_model(path);
  constexpr int kFresh = 8;
  const std::uint64_t fresh_base = model.radiation.seed + 0x5DEECE66Dull;  // neither search nor verification
  std::printf("model %s, %s strategy, %d fresh seeds per model\n", path.c_str(), uniform ? "uniform" : "informed", kFresh);
  std::printf("%8s %7s %7s %22s %10s %12s %12s %24s %8s %7s %8s\n", "tol K", "faces", "kept", "estimate +- SE K", "bound K",
              "8-mean K", "worst pair K", "as loaded: mean +- SE K", "worst K", "within", "time s");
  for (double tol : tolerances) {
    const auto t0 = std::chrono::steady_clock::now();
    ReduceSettings s;
    s.tolerance_K = tol;
    s.strategy = uniform ? ReductionStrategy::uniform : ReductionStrategy::informed;
    const ReductionRun run = reduce_model(model, s);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // The reduced model keeps the search's sampling boosts; the original gets the same ones.
    ThermalModel orig = model, red = run.reduced.model;
    for (std::size_t k = 0; k < orig.nodes.size(); ++k) orig.nodes[k].sampling_boost = red.nodes[k].sampling_boost;
    ThermalModel loaded = model;
    std::vector<SimulationResult> a, b, c;
    for (int j = 0; j < kFresh; ++j) {
      orig.radiation.seed = loaded.radiation.seed = fresh_base + 2 * j;
      red.radiation.seed = fresh_base + 2 * j + 1;
      a.push_back(simulate_model(orig, s.reference.simulation));
      b.push_back(simulate_model(red, s.reference.simulation));
      // As cmd_simulate does for a model without boosts (its --noise-target defaults).
      const SamplingBoosts boosts = decide_sampling_boosts(loaded, s.reference.simulation, 0.0025, 32.0, 2e8);
      ThermalModel boosted = loaded;
      for (std::size_t k = 0; k < boosted.nodes.size(); ++k) boosted.nodes[k].sampling_boost = boosts.boost[k];
      c.push_back(simulate_model(boosted, s.reference.simulation));
    }
    Eigen::MatrixXd ma = Eigen::MatrixXd::Zero(a[0].temperature_K.rows(), a[0].temperature_K.cols()), mb = ma;
    double worst = 0.0, worst_loaded = 0.0, sum = 0.0, sum2 = 0.0;
    int within = 0;
    for (int i = 0; i < kFresh; ++i) {
      ma += a[i].temperature_K / kFresh;
      mb += b[i].temperature_K / kFresh;
      for (int j = 0; j < kFresh; ++j) {
        worst = std::max(worst, compare_results(a[i], b[j]).max_abs_K);
        const double d = compare_results(c[i], b[j]).max_abs_K;
        worst_loaded = std::max(worst_loaded, d);
        sum += d;
        sum2 += d * d;
        within += d <= tol;
      }
    }
    const VerificationStatistics& v = run.verification;
    const int pairs = kFresh * kFresh;
    const double mean = sum / pairs, se = std::sqrt(std::max(0.0, sum2 / pairs - mean * mean) / (pairs - 1));
    std::printf("%8.3g %7d %7d %12.4f +- %.4f %10.4f %12.4f %12.4f %14.4f +- %.4f %8.4f %4d/%d %8.0f\n", tol,
                run.faces_before, run.faces_after, v.max_abs_dT_K, v.standard_error_K, v.upper_bound_K,
                (mb - ma).cwiseAbs().maxCoeff(), worst, mean, se, worst_loaded, within, pairs, secs);
    std::fflush(stdout);
  }
  return 0;
}
