#include "thermodec/reduction/reduce_model.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <tbb/parallel_for.h>

#include "thermodec/common/errors.h"
#include "thermodec/common/release_free_memory.h"
#include "thermodec/common/side_by_side.h"
#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/decimation/global_ratio.h"
#include "thermodec/reduction/area_bounds.h"
#include "thermodec/reduction/prediction.h"
#include "thermodec/reduction/record_budget.h"
#include "thermodec/reduction/statistical_verification.h"
#include "thermodec/reduction/verification_back_off.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

// One progress line on the reference's ray records: kept, or left out and why.
std::string describe_records(const RecordUse& u) {
  constexpr double GiB = 1073741824.0;
  std::string s = u.ir_bytes > 0 ? fmt("ray records: IR %.2f GiB", u.ir_bytes / GiB)
                                 : fmt("ray records: IR left out (%.2f GiB over its %.2f GiB)", u.ir_needed_bytes / GiB,
                                       u.ir_budget_bytes / GiB);
  s += u.loads_kept ? fmt(", sun/Earth %.2f GiB", u.load_bytes / GiB)
                    : fmt(", sun/Earth left out (over %.2f GiB)", u.load_budget_bytes / GiB);
  if (u.ir_bytes == 0 || !u.loads_kept) s += ": trials trace more rays (--record-memory raises the budget)";
  s += fmt("; beside them view factors %.2f GiB, Earth hits %.2f GiB", u.view_factor_bytes / GiB, u.earth_hit_bytes / GiB);
  return s;
}
}  // namespace

void apply_bare_mesh_reduction_budget(ThermalModel& model, ReduceSettings& settings) {
  if (!model.mesh_cleanup) return;
  apply_bare_mesh_ray_budgets(model, settings.reference.simulation);
  if (model.mesh.num_faces() > kBareMeshCoarseSweepFaces) {
    settings.sensitivity.ratios = {0.5, 0.8, 0.93};
    settings.sensitivity.ratios_beyond = {0.96, 0.98};  // where 0.93 reached its face count
    settings.informed.max_evaluations = std::min(settings.informed.max_evaluations, 20);
    settings.informed.max_leave_one_out = 8;  // two back-off steps fit in the 20 trials
    settings.informed.max_push_trials = 6;    // each about a full simulation (strategies.h)
    settings.informed.max_combined_push_trials = std::min(settings.informed.max_combined_push_trials, 6);
    settings.prediction_targets = {1.0};      // (the search's first candidate: no extra trial)
  }
}

void apply_large_model_sweep(const ThermalModel& model, ReduceSettings& settings) {
  if (model.mesh_cleanup || model.mesh.num_faces() <= kBareMeshCoarseSweepFaces) return;
  // Trials of a large model cost seconds each: the small models' 80 would add minutes.
  settings.informed.max_evaluations = std::min(settings.informed.max_evaluations, 40);
  settings.sensitivity.ratios.clear();
  for (int k = 1; k <= 7; ++k) settings.sensitivity.ratios.push_back(1.0 - std::exp2(-k));
  settings.prediction_targets = {1.0};
}

namespace {

// The strategy search over one set of references (one per load case), at a given tolerance.
struct Searcher {
  const ReduceSettings& settings;
  const std::vector<std::unique_ptr<ReductionReference>>& refs;
  const Eigen::VectorXi& faces;
  int n;
  // The search's evaluations are trials: bit-identical to a full recompute with the search's
  // seed (reduction_reference.h), so the strategies' confirming evaluation is the trial itself.
  std::function<TrialResult(const Eigen::VectorXd&)> trial;
  std::function<void(const Eigen::VectorXd&, const TrialResult&, int)> before_push;  // InformedOptions
  std::function<void(const std::string&)> log, say;
  std::function<int()> trials_evaluated;
  std::vector<std::string> node_names;  // for progress lines and history actions

  // Informed: each node alone on increasing ratios (once; the curves serve every attempt).
  void sweep(ReductionRun& run) const {
    SensitivityOptions so = settings.sensitivity;
    const double tol = settings.tolerance_K;
    so.cap_K = settings.sensitivity_cap_factor * tol;
    // A node beyond the tolerance at the first ratio is tried at smaller ones (halvings).
    so.refine_first_above_K = std::min(so.refine_first_above_K, tol);
    if (!so.ratios_beyond.empty()) so.node_faces_before.assign(faces.data(), faces.data() + faces.size());
    const auto ts = Clock::now();
    so.progress = [&](int done, int total) {
      // Time left, extrapolated from the nodes swept so far (rough: sweeps differ in length).
      const double spent = since(ts), left = done > 0 ? spent / done * (total - done) : 0.0;
      say("  sensitivity: " + std::to_string(done) + "/" + std::to_string(total) + " nodes swept (" +
          std::to_string(trials_evaluated()) + " trials, " +
          (done < total ? fmt("about %.0f s left)", left) : fmt("%.0f s)", spent)));
    };
    say("sensitivity analysis: each node alone, increasing ratios, cap " + fmt("%.3g K", so.cap_K));
    SweepOutcome sw = settings.sweep ? settings.sweep(n, trial, so, faces, trials_evaluated)
                                     : SweepOutcome{sensitivity_analysis(n, trial, so)};
    run.seconds_sensitivity = since(ts);
    run.trials = sw.trials_elsewhere;  // (this process's trials added at the end)
    run.peak_memory_bytes_other_ranks = sw.peak_memory_bytes_elsewhere;
    run.sweep_only = sw.stop_after_sweep;
    run.curves = std::move(sw.curves);
  }

  ReductionOutcome at(const ReductionRun& run, double search_tol) const {
    if (settings.strategy == ReductionStrategy::uniform) {
      const ReductionReference& ref = *refs.front();
      const Eigen::VectorXd reachable = ref.max_ratio_per_node();
      auto ratios_for_global = [&](double g) {
        return node_ratios_for_global_ratio(faces, g, settings.reference.decimation.min_faces_per_node, reachable);
      };
      UniformOptions uo = settings.uniform;
      uo.tolerance_K = search_tol;
      uo.log = log;
      say("uniform reduction: one global ratio, raised until " + fmt("%.4g K is exceeded", search_tol));
      return uniform_reduction(ratios_for_global, trial, trial, uo);
    }
    InformedOptions io = settings.informed;
    io.tolerance_K = search_tol;
    io.log = log;
    io.node_names = node_names;
    io.before_push = before_push;
    io.node_faces = [this](const Eigen::VectorXd& r) {  // decimation only (ms to 0.1 s on NPP_16)
      const ReductionReference& ref = *refs.front();
      const DecimationResult d = decimate_nodes(ref.model().mesh, r, ref.decimation_options());
      Eigen::VectorXi faces_k = Eigen::VectorXi::Zero(r.size());
      for (Eigen::Index k = 0; k < r.size() && k < static_cast<Eigen::Index>(d.nodes.size()); ++k)
        faces_k[k] = d.nodes[k].faces_after;
      return faces_k;
    };
    say("prediction and reduction aiming at " + fmt("%.4g K", search_tol));
    return informed_reduction(run.curves, n, trial, trial, io);
  }

  // Predicted vs real (paper Fig. 11): for several targets, the curves' prediction and the
  // simulated difference of all nodes reduced together. `tol` is the search tolerance: the
  // 1.0 target's candidate is then the search's first, taken from the trial memo.
  void predictions(ReductionRun& run, double tol) const {
    run.prediction.resize(settings.prediction_targets.size());
    tbb::parallel_for(size_t(0), settings.prediction_targets.size(), [&](size_t i) {
      PredictionPoint& p = run.prediction[i];
      p.target_K = settings.prediction_targets[i] * tol;
      Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
      for (const auto& c : run.curves) {
        r[c.node] = feasible_ratio(c, p.target_K);
        p.predicted_K = std::max(p.predicted_K, predicted_difference_K(c, r[c.node]));
      }
      const TrialResult t = trial(r);
      p.real_K = t.max_abs_dT_K;
      p.faces_after = t.faces_after;
    });
  }
};

// Statistical verification of the candidate `ratios` in every load case (fresh seeds).
VerificationStatistics verify_ratios(const std::vector<std::unique_ptr<ReductionReference>>& refs,
                                     const Eigen::VectorXd& ratios, const ReduceSettings& settings,
                                     std::uint64_t search_seed, VerificationOriginals& originals) {
  std::vector<Candidate> cands;  // (the search's trial of these ratios: decimated again, not simulated)
  for (const auto& r : refs) cands.push_back(r->candidate(ratios, false));
  if (settings.verify_candidate) {
    std::vector<const ThermalModel*> models;
    for (const Candidate& c : cands) models.push_back(&c.model);
    return settings.verify_candidate(models);
  }
  std::vector<VerificationCase> cases;
  for (std::size_t c = 0; c < refs.size(); ++c) cases.push_back({&refs[c]->model(), &cands[c].model});
  return verify_statistically(cases, settings.reference.simulation, settings.verification_replicates, search_seed,
                              &originals);
}

// The search aims below the tolerance by a margin from the measured noise, so that the
// statistical verification (upper bound at 97.5 %) rarely rejects: the per-cell standard
// deviation sigma of a seed pair's difference is taken as noise floor / 3 (the noise floor is
// the max over ~10^3-10^4 node-times of one pair's |dT|, ~3-4 standard deviations). The bound
// adds t(0.975, R - 1) sigma / sqrt(R) to the fresh seeds' mean, and the search's own estimate
// of the candidate is one seed's, sigma off the fresh seeds' mean (and the search keeps the
// candidates whose estimate fell under its aim: the error it keeps is the favourable one), so
// the margin is (t / sqrt(R) + 1) sigma. (NPP_16 at 0.5 K: the search measured 0.467 K and
// 0.461 K where 4 fresh pairs gave 0.486 +- 0.007 K and 0.482 +- 0.005 K, 1.4-1.6 sigma over;
// with the first term alone the search aimed at 0.478 K and its first candidate was rejected.)
// A rejected candidate widens the margin by the bound's excess over the tolerance; after the
// last attempt the unreduced model is kept.
double first_search_margin_K(double noise_floor_K, int R) {
  const double sigma = noise_floor_K / 3.0;
  return (student_t_975(R - 1) / std::sqrt(double(R)) + 1.0) * sigma;
}

// `originals`: the original's verification runs so far (the noise floor's), kept for every attempt.
void verified_search(ReductionRun& run, const Searcher& search,
                     const std::vector<std::unique_ptr<ReductionReference>>& refs, const ReduceSettings& settings,
                     std::uint64_t search_seed, VerificationOriginals& originals,
                     const std::function<void(const std::string&)>& say) {
  const double tol = settings.tolerance_K;
  const double vtol = settings.verification_tolerance_K > 0.0 ? settings.verification_tolerance_K : tol;
  const int R = settings.verification_replicates;
  double margin = first_search_margin_K(run.noise_floor_K, R);
  bool accepted = false;
  ReductionOutcome least;  // the rejected candidate of least upper bound
  double least_bound = std::numeric_limits<double>::infinity();
  for (int attempt = 0; attempt < settings.verification_attempts && !accepted && margin < tol; ++attempt) {
    run.search_tolerance_K = tol - margin;
    try {
      run.outcome = search.at(run, run.search_tolerance_K);
    } catch (const SolverError& e) {  // the noise exceeds the narrowed target
      say(std::string("search at ") + fmt("%.4g K failed: ", run.search_tolerance_K) + e.what());
      break;
    }
    const auto tv = Clock::now();
    say(fmt("verification: %.0f replicate pairs with fresh seeds", R));
    run.verification = verify_ratios(refs, run.outcome.ratio_per_node, settings, search_seed, originals);
    run.seconds_verification += since(tv);
    say(fmt("verification: max |dT| = %.4f +- %.4f K (upper bound %.4f K at 97.5 %%)", run.verification.max_abs_dT_K,
            run.verification.standard_error_K, run.verification.upper_bound_K));
    accepted = run.verification.accepts(vtol);
    if (!accepted && run.verification.upper_bound_K < least_bound)
      least = run.outcome, least_bound = run.verification.upper_bound_K;
    if (!accepted) margin += std::max(run.verification.upper_bound_K - vtol, 0.0) + run.verification.standard_error_K;
  }
  if (accepted) return;
  VerificationStatistics backed;
  const auto tb = Clock::now();
  const double s = back_off_scale(std::isfinite(least_bound) ? settings.back_off_verifications : 0, [&](double a) {
    say(fmt("verification: backing off, the least rejected candidate's ratios x %.3g", a));
    const VerificationStatistics v = verify_ratios(refs, a * least.ratio_per_node, settings, search_seed, originals);
    say(fmt("verification: max |dT| = %.4f +- %.4f K (upper bound %.4f K at 97.5 %%)", v.max_abs_dT_K,
            v.standard_error_K, v.upper_bound_K));
    if (v.accepts(vtol)) backed = v;
    return v.accepts(vtol);
  });
  run.seconds_verification += since(tb);
  if (s > 0.0) {
    run.outcome = least;
    run.outcome.ratio_per_node = s * least.ratio_per_node;
    run.outcome.verified = search.trial(run.outcome.ratio_per_node);
    run.outcome.history.push_back({run.outcome.ratio_per_node, run.outcome.verified, true, fmt("back off x%.3g", s)});
    return void(run.verification = backed);
  }
  say("verification: no reduced candidate is bounded within the tolerance; keeping the unreduced model");
  ReductionOutcome keep;
  keep.ratio_per_node = Eigen::VectorXd::Zero(refs.front()->faces_per_node().size());
  keep.verified = search.trial(keep.ratio_per_node);
  keep.predicted_ratio_per_node = run.outcome.predicted_ratio_per_node;
  keep.history = run.outcome.history;
  run.outcome = keep;
  const auto tv = Clock::now();
  run.verification = verify_ratios(refs, keep.ratio_per_node, settings, search_seed, originals);
  run.seconds_verification += since(tv);
  if (!run.verification.accepts(vtol))
    throw SolverError(fmt("even the unreduced model's upper bound (%.4g K at 97.5 %%) exceeds the tolerance %.4g K: "
                          "the simulation noise exceeds the tolerance",
                          run.verification.upper_bound_K, vtol));
}

// A kind of samples thinned on some nodes but not on all (load cases that disagree) is not
// thinned at all: thinning is one factor common to every node (noise_targeted_thinning).
void keep_thinning_common(std::vector<Node>& nodes) {
  bool ir_mixed = false, loads_mixed = false;
  for (const Node& n : nodes) {
    ir_mixed = ir_mixed || (n.sampling_boost.ir < 1.0) != (nodes.front().sampling_boost.ir < 1.0);
    loads_mixed = loads_mixed || (n.sampling_boost.loads < 1.0) != (nodes.front().sampling_boost.loads < 1.0);
  }
  for (Node& n : nodes) {
    if (ir_mixed) n.sampling_boost.ir = std::max(1.0, n.sampling_boost.ir);
    if (loads_mixed) n.sampling_boost.loads = std::max(1.0, n.sampling_boost.loads);
  }
}

// Noise-targeted sampling: decides the boosts of every load case into `boosted`; false if off.
bool boost_sampling(const ThermalModel& model_in, const ReduceSettings& settings,
                    const std::function<void(const std::string&)>& say, ThermalModel& boosted) {
  const double tol = settings.tolerance_K;
  // Noise-targeted sampling: the few nodes whose temperature the couplings' noise moves most
  // get more samples, decided once here and kept by every trial and by the reduced model.
  const bool boost = settings.noise_target_fraction > 0.0 && !has_sampling_boosts(model_in);
  if (boost) {
    say(fmt("sampling: estimating each node's Monte Carlo noise (target %.3g K)", settings.noise_target_fraction * tol));
    const double min_boost = settings.thin_oversampling ? Node::SamplingBoost::kMin : 1.0;
    const double inf = std::numeric_limits<double>::infinity();
    const SamplingBoosts b = decide_sampling_boosts(model_in, settings.reference.simulation,
                                                    settings.noise_target_fraction * tol, 2.0, inf, min_boost);
    boosted = model_in;
    for (std::size_t k = 0; k < b.boost.size(); ++k) boosted.nodes[k].sampling_boost = b.boost[k];
    say(b.describe(model_in.nodes));
    // Every load case decides too (another attitude samples the Earth differently, another
    // date shadows other nodes); a node keeps the largest boost any case asks for, and a kind
    // stays thinned only where every case thins it (one common factor, or none).
    for (const LoadCase& c : settings.extra_cases) {
      const SamplingBoosts bc = decide_sampling_boosts(with_case(model_in, c), settings.reference.simulation,
                                                       settings.noise_target_fraction * tol, 2.0, inf, min_boost);
      for (std::size_t k = 0; k < bc.boost.size(); ++k) {
        auto& nb = boosted.nodes[k].sampling_boost;
        nb.ir = std::max(nb.ir, bc.boost[k].ir);
        nb.loads = std::max(nb.loads, bc.boost[k].loads);
      }
      say("case " + c.name + ": " + bc.describe(model_in.nodes));
    }
    keep_thinning_common(boosted.nodes);
    release_free_memory();  // (the pilot simulations' blocks)
  }
  return boost;
}

// The returned model rebuilt in full, its difference per case and per node.
void rebuild_and_report(ReductionRun& run, const std::vector<std::unique_ptr<ReductionReference>>& refs,
                        const std::vector<LoadCase>& cases, const ThermalModel& model) {
  const double tol = run.tolerance_K;
  const ReductionReference& ref = *refs.front();
  const int n = static_cast<int>(model.nodes.size());
  // The returned model is the verified candidate, decimated again, and its difference in
  // every case (the search's trial, bit-identical to a full recompute: taken from memory).
  run.reduced = ref.candidate(run.outcome.ratio_per_node, false);
  run.faces_after = run.reduced.model.mesh.num_faces();
  Eigen::VectorXd node_max = run.reduced.trial.node_max_abs_dT_K;
  for (std::size_t c = 0; c < refs.size(); ++c) {
    TemperatureDifference d = run.reduced.difference;
    if (c > 0) {
      const Candidate other = refs[c]->candidate(run.outcome.ratio_per_node, false);
      d = other.difference;
      node_max = node_max.cwiseMax(other.trial.node_max_abs_dT_K);
    }
    run.cases[c].max_temperature_difference_K = d.max_abs_K;
    run.cases[c].max_difference_node = d.node;
    run.cases[c].max_difference_time_s = d.time_s;
    if (c == 0 || d.max_abs_K > run.max_temperature_difference_K) {
      run.max_temperature_difference_K = d.max_abs_K;
      run.max_difference_node = d.node;
      run.max_difference_case = cases[c].name;
      run.max_difference_time_s = d.time_s;
    }
  }
  if (!(run.max_temperature_difference_K <= tol))  // cannot happen: the strategies verified it
    throw SolverError("internal: the verified model exceeds the tolerance on rebuild");
  for (int k = 0; k < n; ++k) {
    NodeReduction nr;
    nr.name = model.nodes[k].name;
    const auto& st = run.reduced.decimation.nodes[k];
    nr.faces_before = st.faces_before;
    nr.faces_after = st.faces_after;
    nr.requested_ratio = run.outcome.ratio_per_node[k];
    nr.ratio = 1.0 - static_cast<double>(st.faces_after) / std::max(1, st.faces_before);
    nr.predicted_ratio = run.outcome.predicted_ratio_per_node.size() ? run.outcome.predicted_ratio_per_node[k] : 0.0;
    nr.max_abs_dT_K = node_max[k];
    nr.area_before_m2 = st.area_before_m2;
    nr.area_after_m2 = st.area_after_m2;
    nr.target_faces = st.target_faces;
    nr.stopped_by = collapse_block_name(st.stopped_by());
    for (int b = 0; b < kCollapseBlocks; ++b)
      if (st.blocked_edges[b] > 0) nr.blocked_edges.emplace_back(collapse_block_name(static_cast<CollapseBlock>(b)), st.blocked_edges[b]);
    run.nodes.push_back(nr);
  }
}

// Pushes move one node at a time from a candidate reduced in many nodes; against the original,
// each such trial redoes about what the start candidate's own trial did (tdrs: all but 12 of
// 18 237 view-factor rows, ~21 s, a whole simulation). Rebasing every case's reference on the start candidate
// (ReductionReference::rebase) costs about one reference build, ~1.75 simulations (NPP_16 1.8,
// Juno 1.75, tdrs 1.6), and makes each push about a one-node trial. Done when the push trials
// to expect would cost over twice that build, in simulations (the redone share, not the
// time: the decision, and so the results' last digits, must not depend on machine load), and
// only with the record memory the references left unused (their budget is the run's).
void rebase_for_pushes(const std::vector<std::unique_ptr<ReductionReference>>& refs, const Eigen::VectorXd& start,
                       const TrialResult& start_result, int trials_left, std::size_t case_budget_bytes,
                       const std::function<void(const std::string&)>& log) {
  constexpr double kReferenceBuildInSimulations = 1.75;
  if (!(trials_left * start_result.redone_fraction > 2.0 * kReferenceBuildInSimulations)) return;
  std::vector<std::size_t> left;
  for (const auto& r : refs) {
    const RecordUse& u = r->record_use();
    const std::size_t used = u.ir_bytes + u.load_bytes;
    // The start candidate's records take about the original's share per face; without room for
    // them, its trials would re-trace without records and lose what rebasing gains.
    const double share = static_cast<double>(start_result.faces_after) / std::max(1, r->faces_per_node().sum());
    const std::size_t room = used < case_budget_bytes ? case_budget_bytes - used : 0;
    if (room < share * static_cast<double>(u.ir_needed_bytes + u.load_bytes)) return;
    left.push_back(room);
  }
  const auto t0 = Clock::now();
  for (std::size_t c = 0; c < refs.size(); ++c) refs[c]->rebase(start, left[c]);
  release_free_memory();
  log(fmt("rebased on the push's start candidate (%.0f s) for about %.0f push trials redoing %.0f %% of a "
          "simulation each: each now re-traces only what differs from it", since(t0), trials_left,
          100.0 * start_result.redone_fraction));
}

// Per-node area bounds (reduction/area_bounds.h): budget_K against each node's sensitivity to
// its area, the largest over the cases, at most `cap`; set on every case's reference.
void set_node_area_bounds(const std::vector<std::unique_ptr<ReductionReference>>& refs, double budget_K, double cap,
                          DecimationOptions& dec, const std::function<void(const std::string&)>& say) {
  Eigen::VectorXd s;
  for (const auto& r : refs) {
    const Eigen::VectorXd sr = area_sensitivity_K(thermal_network(r->model(), r->couplings()), r->result().temperature_K);
    s = s.size() == 0 ? sr : Eigen::VectorXd(s.cwiseMax(sr));
  }
  dec.node_max_relative_area_change = node_area_bounds(s, budget_K, std::max(cap, dec.max_relative_area_change));
  for (auto& r : refs) r->set_decimation_options(dec);
  std::vector<double> sorted = dec.node_max_relative_area_change;
  std::sort(sorted.begin(), sorted.end());
  if (sorted.empty()) return;
  say(fmt("decimation: per-node area bounds from each node's sensitivity (T dA/4A alone in space, less in balance "
          "with its surroundings): %.3g / %.3g / %.3g %% (min / median / max)",
          100.0 * sorted.front(), 100.0 * sorted[sorted.size() / 2], 100.0 * sorted.back()));
}

// A merged model's trials are read per original node within each node's budget (node_budget.h):
// one budget per case, at the first attempt's search tolerance (verified_search's margin).
// Empty without settings.node_budget.
std::vector<NodeBudget> node_budgets(const std::vector<std::unique_ptr<ReductionReference>>& refs,
                                     const ReduceSettings& settings, double noise_floor_K) {
  std::vector<NodeBudget> budgets;
  if (!settings.node_budget) return budgets;
  const int R = settings.verification_replicates;
  const double s = settings.tolerance_K - first_search_margin_K(noise_floor_K, R);
  for (std::size_t c = 0; c < refs.size(); ++c) budgets.push_back(settings.node_budget(c, refs[c]->result(), s));
  return budgets;
}

// The reference of one case (appended to `refs`) and its noise floor: the same model simulated
// with `runs` - 1 other seeds, the verification's first ones (verification_seeds: no trial
// draws from them); those runs are moved to `other_runs`, the first pairs' originals. Every
// run is independent of the others, so they run side by side (run_side_by_side): the
// reference's build and a whole simulation fill each other's idle core.
NoiseFloor reference_and_noise_floor(const ThermalModel& model, const ReductionReferenceSettings& settings, int runs,
                                     std::vector<std::unique_ptr<ReductionReference>>& refs,
                                     std::vector<SimulationResult>& other_runs) {
  std::unique_ptr<ReductionReference> ref;
  std::vector<SimulationResult> results(runs);
  std::vector<std::uint64_t> seeds(runs);
  std::vector<double> run_time_s(runs - 1);
  const std::vector<std::uint64_t> others = verification_seeds(model.radiation.seed, runs - 1);
  run_side_by_side(runs, 2, [&](int k) {
    if (k == 0) {
      ref = std::make_unique<ReductionReference>(model, settings);
      return;
    }
    ThermalModel m = model;
    m.radiation.seed = others[k - 1];
    const auto t0 = Clock::now();
    results[k] = simulate_model(m, settings.simulation);
    run_time_s[k - 1] = since(t0);
  });
  results[0] = ref->result();
  seeds[0] = model.radiation.seed;
  for (int k = 1; k < runs; ++k) seeds[k] = others[k - 1];
  refs.push_back(std::move(ref));
  other_runs.assign(results.begin() + 1, results.end());
  NoiseFloor noise = noise_floor_of(std::move(results), std::move(seeds));
  noise.run_time_s = std::move(run_time_s);
  return noise;
}

}  // namespace

ReductionRun reduce_model(const ThermalModel& model_in, const ReduceSettings& settings_in) {
  // Earth view by cone rays in reference, trials and verification alike: their per-ray records
  // let a trial re-trace only the rays that can meet the change, where a rasterised side is
  // computed again whole (sample at 0.5 K: sweep 40 s against 63 s with the raster).
  ReduceSettings settings = settings_in;
  settings.reference.simulation.loads.earth_view_by_rays = true;
  // Likewise IR rows counted ray by ray (no planar strata): a trial moves single rays' hits.
  settings.reference.simulation.planar_strata = false;
  const double tol = settings.tolerance_K;
  if (!std::isfinite(tol) || tol <= 0)
    throw InvalidInput("tolerance must be a finite temperature difference > 0 K (got " + std::to_string(tol) + ")");
  if (settings.noise_runs < 2) throw InvalidInput("noise_runs must be >= 2");
  if (!(settings.noise_target_fraction >= 0.0)) throw InvalidInput("noise_target_fraction must be >= 0");
  if (!(settings.area_error_fraction >= 0.0 && settings.area_error_fraction <= 1.0))
    throw InvalidInput("area_error_fraction must be in [0, 1]");
  auto say = [&](const std::string& s) { if (settings.progress) settings.progress(s); };
  // Case names tell the per-case results apart (every front end passes cases through here).
  for (std::size_t i = 0; i < settings.extra_cases.size(); ++i) {
    const std::string& nm = settings.extra_cases[i].name;
    bool twice = nm == own_case(model_in).name;
    for (std::size_t j = 0; j < i; ++j) twice |= settings.extra_cases[j].name == nm;
    if (twice) throw InvalidInput("load case name '" + nm + "' is used twice (the model's own case is 'model')");
  }
  const auto t0 = Clock::now();

  ThermalModel boosted;
  const bool boost = boost_sampling(model_in, settings, say, boosted);
  const ThermalModel& model = boost ? boosted : model_in;
  ReductionRun run;
  run.strategy = settings.strategy == ReductionStrategy::informed ? "informed" : "uniform";
  run.tolerance_K = tol;
  run.mesh_cleanup = model.mesh_cleanup;
  run.rays_per_face = model.radiation.rays_per_face;
  for (const Node& nd : model.nodes) run.sampling_boost.push_back(nd.sampling_boost);
  run.sun_rays_per_face = settings.reference.simulation.loads.sun_rays_per_face;

  // The reference of each load case (simulated once, with its reusable rays and samples), then
  // its noise floor: the same simulation with other seeds. A tolerance the Monte Carlo noise
  // could eat is refused before any reduction work.
  std::vector<LoadCase> cases{own_case(model)};
  for (const LoadCase& c : settings.extra_cases) cases.push_back(c);
  const bool several = cases.size() > 1;
  std::vector<std::unique_ptr<ReductionReference>> refs;
  VerificationOriginals originals;  // the original's verification runs: the noise floor's, then the rest
  // The record budget is the run's: every case's reference keeps its records at once, so each
  // gets an equal share.
  ReductionReferenceSettings per_case = settings.reference;
  per_case.record_budget_bytes = record_budget_bytes(settings.reference.record_budget_bytes) / cases.size();
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const std::string tag = several ? "case " + cases[c].name + ": " : "";
    say(tag + "reference: simulating and keeping reusable rays and samples, beside the noise floor's " +
        std::to_string(settings.noise_runs - 1) + " run(s) with other seeds");
    std::vector<SimulationResult> other_runs;
    const NoiseFloor noise =
        reference_and_noise_floor(with_case(model, cases[c]), per_case, settings.noise_runs, refs, other_runs);
    // The noise floor's runs are the verification's first originals (their seeds are s_0, ...).
    const std::vector<std::uint64_t> vs = verification_seeds(model.radiation.seed, settings.verification_replicates);
    originals.per_case.emplace_back();
    for (std::size_t j = 0; j < other_runs.size() && j < vs.size() && noise.seeds[j + 1] == vs[j]; ++j)
      originals.per_case.back().push_back(std::move(other_runs[j]));
    release_free_memory();  // (the reference's tracing and load sampling: every trial runs beside what is left)
    say(tag + describe_records(refs.back()->record_use()));
    CaseResult cr;
    cr.name = cases[c].name;
    cr.noise_floor_K = noise.worst.max_abs_K;
    const RecordUse use = refs[c]->record_use();
    cr.ray_record_bytes = use.ir_bytes + use.load_bytes;
    cr.view_factor_bytes = use.view_factor_bytes;
    cr.earth_hit_bytes = use.earth_hit_bytes;
    cr.ray_record_budget_bytes = per_case.record_budget_bytes;
    run.cases.push_back(cr);
    run.noise_floor_K = std::max(run.noise_floor_K, cr.noise_floor_K);
    say(tag + fmt("noise floor %.4f K (%.1f s per simulation)", cr.noise_floor_K,
                  noise.run_time_s.empty() ? 0.0 : noise.run_time_s.front()));
  }
  run.seconds_noise = since(t0);
  if (tol < 2.0 * run.noise_floor_K)
    throw InvalidInput(fmt("tolerance %.4g K is below twice the measured noise floor (%.4g K): "
                           "ask for at least %.4g K or raise radiation.rays_per_face",
                           tol, run.noise_floor_K, 2.0 * run.noise_floor_K));

  // The decimator's area bound from the tolerance (ReduceSettings::area_error_fraction): at
  // 0.5 K and ~300 K, 0.07 % instead of the decimator's default 0.5 %, which alone moves a
  // radiating node by ~0.4 K (measured on tdrs, docs/benchmarks.md).
  DecimationOptions dec = refs.front()->decimation_options();
  double t_max = 0.0;
  for (const auto& r : refs) t_max = std::max(t_max, r->result().temperature_K.maxCoeff());
  const double area_cap = dec.max_relative_area_change;
  if (settings.area_error_fraction > 0.0 && t_max > 0.0 && std::isfinite(t_max)) {
    const double bound = 4.0 * settings.area_error_fraction * tol / t_max;
    if (bound < dec.max_relative_area_change) {
      dec.max_relative_area_change = bound;
      for (auto& r : refs) r->set_decimation_options(dec);
    }
  }
  say(fmt("decimation: node areas kept within %.3g %% (area drift T dA/4A <= %.3g K at T_max %.1f K)",
          100.0 * dec.max_relative_area_change, t_max * dec.max_relative_area_change / 4.0, t_max) +
      (settings.area_error_fraction > 0.0 ? "" : ", bound as given"));
  run.max_relative_area_change = dec.max_relative_area_change;
  if (settings.area_error_fraction > 0.0 && settings.per_node_area_bound) {
    set_node_area_bounds(refs, settings.area_error_fraction * tol, area_cap, dec, say);
    run.node_max_relative_area_change = dec.node_max_relative_area_change;
  }
  if (dec.reflection_cap > 0.0) {
    // Reflected-sunlight cap (docs/decimation.md): the reference's reflected fluxes, mean over the cases.
    // Fluxes and absorbed powers: mean over the cases (the views are the geometry's).
    DecimationOptions::ReflectionData mean = refs.front()->reflection();
    for (size_t k = 1; k < refs.size(); ++k) {
      const auto& r = refs[k]->reflection();
      for (size_t i = 0; i < mean.flux_W_per_m2.size() && i < r.flux_W_per_m2.size(); ++i) mean.flux_W_per_m2[i] += r.flux_W_per_m2[i];
      for (size_t i = 0; i < mean.node_absorbed_W.size() && i < r.node_absorbed_W.size(); ++i) mean.node_absorbed_W[i] += r.node_absorbed_W[i];
    }
    for (double& q : mean.flux_W_per_m2) q /= static_cast<double>(refs.size());
    for (double& q : mean.node_absorbed_W) q /= static_cast<double>(refs.size());
    dec.reflection = std::move(mean);
    for (auto& r : refs) r->set_decimation_options(dec);
  }

  const ReductionReference& ref = *refs.front();
  run.reference = ref.result();
  run.reference_mesh = model.mesh;
  const int n = static_cast<int>(model.nodes.size());
  const Eigen::VectorXi faces = ref.faces_per_node();
  run.faces_before = faces.sum();
  // Every case sees the same decimated mesh (decimation does not depend on the environment);
  // a candidate's difference is the worst over the cases, node by node.
  const std::vector<NodeBudget> budgets = node_budgets(refs, settings, run.noise_floor_K);
  auto case_trial = [&](std::size_t c, const Eigen::VectorXd& r) {
    return budgets.empty() ? refs[c]->trial(r) : within_node_budget(refs[c]->trial(r), budgets[c]);
  };
  auto trial = [&](const Eigen::VectorXd& r) {
    TrialResult t = case_trial(0, r);
    for (std::size_t c = 1; c < refs.size(); ++c) {
      const TrialResult o = case_trial(c, r);
      t.max_abs_dT_K = std::max(t.max_abs_dT_K, o.max_abs_dT_K);
      t.node_max_abs_dT_K = t.node_max_abs_dT_K.cwiseMax(o.node_max_abs_dT_K);
      if (t.dT_K.rows() == o.dT_K.rows()) {  // the cases' fields side by side
        Eigen::MatrixXd both(t.dT_K.rows(), t.dT_K.cols() + o.dT_K.cols());
        both << t.dT_K, o.dT_K;
        t.dT_K = std::move(both);
      }
      t.timing.decimation_s += o.timing.decimation_s;
      t.timing.couplings_s += o.timing.couplings_s;
      t.timing.loads_s += o.timing.loads_s;
      t.timing.solve_s += o.timing.solve_s;
      t.timing.simulation_s += o.timing.simulation_s;
      t.redone_fraction = std::max(t.redone_fraction, o.redone_fraction);
    }
    return t;
  };
  auto trials_evaluated = [&] {
    int k = 0;
    for (const auto& rf : refs) k += rf->trials_evaluated();
    return k;
  };
  auto log = [&](const std::string& s) { say("  " + s); };

  const auto t_search = Clock::now();
  std::vector<std::string> names;
  for (const Node& nd : model.nodes) names.push_back(nd.name);
  auto before_push = [&](const Eigen::VectorXd& start, const TrialResult& start_result, int trials_left) {
    rebase_for_pushes(refs, start, start_result, trials_left, per_case.record_budget_bytes, log);
  };
  const Searcher search{settings, refs, faces, n, trial, before_push, log, say, trials_evaluated, names};
  if (settings.strategy == ReductionStrategy::informed) {
    search.sweep(run);
    if (run.sweep_only) return run;  // an MPI rank other than 0: its curves went to rank 0
  }
  verified_search(run, search, refs, settings, model.radiation.seed, originals, say);
  if (settings.strategy == ReductionStrategy::informed)
    search.predictions(run, run.search_tolerance_K > 0.0 ? run.search_tolerance_K : tol);
  run.seconds_search = since(t_search) - run.seconds_verification;

  rebuild_and_report(run, refs, cases, model);
  run.trials += trials_evaluated();  // (trials of other MPI ranks already counted)
  run.seconds_total = since(t0);
  return run;
}

}  // namespace thermodec
