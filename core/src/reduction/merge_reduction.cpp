#include "thermodec/reduction/merge_reduction.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tbb/parallel_for.h>

#include "thermodec/common/errors.h"
#include "thermodec/reduction/node_budget.h"
#include "thermodec/reduction/statistical_verification.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec {
namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
constexpr double kStefanBoltzmann_W_per_m2K4 = 5.670374419e-8;

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

// The original simulated once per load case, kept for the network trials.
struct CaseReference {
  ThermalModel model;
  SimulationResult result;
  NodeCouplings couplings;
};

// Max |dT| over every original node, time and case of the merged network `map` (no tracing).
double merge_trial_K(const std::vector<CaseReference>& refs, const NodeMergeMap& map, const SimulationSettings& solver) {
  double worst = 0.0;
  for (const CaseReference& r : refs) {
    const ThermalModel merged = merge_nodes(r.model, map);
    const SimulationResult m = simulate(merged, merge_couplings(r.couplings, map), merge_loads(r.result.loads, map), solver);
    const TemperatureDifference d = compare_results(r.result, result_through_node_map(m, merged.node_map));
    if (!(d.max_abs_K <= worst)) worst = d.max_abs_K;  // NaN wins
  }
  return worst;
}

NodeMergeMap map_of_labels(const std::vector<int>& labels) { return node_merge_map(labels, static_cast<int>(labels.size())); }

std::vector<std::string> members_named(const ThermalModel& model, const std::vector<int>& labels, int label) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (labels[i] == label) out.push_back(model.nodes[i].name);
  return out;
}

// Labels of the first k accepted merges (in order), from the identity.
std::vector<int> first_merges(const ThermalModel& model, const std::vector<NodeMergeStep>& steps, std::size_t k) {
  const int n = static_cast<int>(model.nodes.size());
  std::vector<int> labels(n);
  for (int i = 0; i < n; ++i) labels[i] = i;
  auto index = [&](const std::string& name) {
    for (int i = 0; i < n; ++i)
      if (model.nodes[i].name == name) return i;
    return -1;
  };
  for (std::size_t s = 0; s < k && s < steps.size(); ++s) {
    const int a = labels[index(steps[s].first.front())], b = labels[index(steps[s].second.front())];
    for (int& x : labels)
      if (x == b) x = a;
  }
  return labels;
}

// The merged model traced (reference seed) against the reference, through the map [K].
double traced_merge_K(const std::vector<CaseReference>& refs, const NodeMergeMap& map,
                      const ModelSimulationSettings& simulation) {
  double worst = 0.0;
  for (const CaseReference& r : refs) {
    const ThermalModel merged = merge_nodes(r.model, map);
    const SimulationResult m = simulate_model(merged, simulation);
    const double d = compare_results(r.result, result_through_node_map(m, merged.node_map)).max_abs_K;
    if (!(d <= worst)) worst = d;
  }
  return worst;
}

// Keeps the longest prefix of the accepted merges whose traced model stays within `limit_K`
// (all of them when they do; k bisected otherwise, at most ~log2(merges) simulations).
std::vector<int> confirmed_by_tracing(const ThermalModel& model, const std::vector<CaseReference>& refs,
                                      const ModelSimulationSettings& simulation, double limit_K, NodeMerging& sum,
                                      const std::function<void(const std::string&)>& say) {
  std::size_t good = 0, bad = sum.steps.size() + 1, k = sum.steps.size();
  double good_dT = 0.0;
  while (k > good && k < bad) {
    const double d = traced_merge_K(refs, map_of_labels(first_merges(model, sum.steps, k)), simulation);
    ++sum.traced_simulations;
    say(fmt("node merging: the first %.0f merges traced: max |dT| %.4f K (limit %.4g K)", k, d, limit_K));
    if (d <= limit_K) good = k, good_dT = d;
    else bad = k;
    k = (good + bad) / 2;
  }
  sum.steps.resize(good);
  sum.traced_dT_K = good_dT;
  sum.dT_K = good > 0 ? sum.steps.back().dT_K : 0.0;
  return first_merges(model, sum.steps, good);
}

}  // namespace

std::vector<std::pair<int, int>> merge_candidates(const ThermalModel& model, const NodeCouplings& couplings,
                                                  const SimulationResult& reference, int strongest,
                                                  const std::vector<int>& excluded) {
  const int n = static_cast<int>(model.nodes.size());
  std::vector<char> out_of_play(n, 0);
  for (int i : excluded) out_of_play.at(i) = 1;
  std::vector<std::pair<int, int>> pairs;
  auto add = [&](int a, int b) {
    if (a == b || a < 0 || b < 0 || a >= n || b >= n || out_of_play[a] || out_of_play[b]) return;
    pairs.emplace_back(std::min(a, b), std::max(a, b));
  };
  // Neighbours: nodes meeting at a mesh edge (their interface is what a merge frees).
  const Mesh& mesh = model.mesh;
  std::map<std::pair<int, int>, int> first_node_of_edge;
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int e = 0; e < 3; ++e) {
      const auto key = std::minmax(mesh.F(f, e), mesh.F(f, (e + 1) % 3));
      const auto it = first_node_of_edge.emplace(key, mesh.face_node[f]).first;
      add(it->second, mesh.face_node[f]);
    }
  // Strong exchanges: conductance GL plus the linearised radiative conductance 4 sigma T^3 GR.
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, n);
  for (const Conductance& c : model.conductances) {
    g(c.from, c.to) += c.conductance_W_per_K;
    g(c.to, c.from) += c.conductance_W_per_K;
  }
  const Eigen::VectorXd t_mean = reference.temperature_K.rowwise().mean();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double t = 0.5 * (t_mean[i] + t_mean[j]);
      if (i != j) g(i, j) += 4.0 * kStefanBoltzmann_W_per_m2K4 * t * t * t * couplings.radiative_couplings_m2(i, j);
    }
  for (int i = 0; i < n; ++i) {
    std::vector<int> order;
    for (int j = 0; j < n; ++j)
      if (j != i && g(i, j) > 0.0) order.push_back(j);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return g(i, a) > g(i, b); });
    for (int k = 0; k < std::min<int>(strongest, static_cast<int>(order.size())); ++k) add(i, order[k]);
  }
  // Near-isothermal nodes, wherever they are: a merge costs about the temperature difference it
  // averages away, so the nodes closest in temperature (max over times) are the cheapest merges.
  const Eigen::MatrixXd& t = reference.temperature_K;
  for (int i = 0; i < n; ++i) {
    std::vector<std::pair<double, int>> near;
    for (int j = 0; j < n; ++j)
      if (j != i) near.emplace_back((t.row(i) - t.row(j)).cwiseAbs().maxCoeff(), j);
    std::stable_sort(near.begin(), near.end());
    for (int k = 0; k < std::min<int>(strongest, static_cast<int>(near.size())); ++k) add(i, near[k].second);
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

MergeSearch search_node_merges(const ThermalModel& model, const std::vector<LoadCase>& extra_cases,
                               const ModelSimulationSettings& simulation, const NodeMergeSettings& merge,
                               double budget_K, const std::function<void(const std::string&)>& say_in) {
  auto say = [&](const std::string& s) { if (say_in) say_in(s); };
  const auto t0 = Clock::now();
  const int n = static_cast<int>(model.nodes.size());
  MergeSearch out;
  NodeMerging& sum = out.summary;
  sum.nodes_before = n;
  sum.budget_K = budget_K;
  // Kept nodes: the user's (checked before any simulation) and every boundary node.
  std::vector<int> excluded = nodes_matching(model, merge.keep);
  for (int i = 0; i < n; ++i)
    if (model.nodes[i].fixed_temperature_K) excluded.push_back(i);
  std::sort(excluded.begin(), excluded.end());
  excluded.erase(std::unique(excluded.begin(), excluded.end()), excluded.end());
  for (int i : excluded) sum.kept.push_back(model.nodes[i].name);

  std::vector<CaseReference> refs;
  std::vector<LoadCase> cases{own_case(model)};
  for (const LoadCase& c : extra_cases) cases.push_back(c);
  for (const LoadCase& c : cases) {
    say("node merging: simulating the original" + (cases.size() > 1 ? " (case " + c.name + ")" : std::string()));
    CaseReference r;
    r.model = with_case(model, c);
    r.result = simulate_model(r.model, simulation, &r.couplings);
    refs.push_back(std::move(r));
  }
  const SimulationSettings& solver = simulation.solver;
  std::vector<int> labels(n);
  for (int i = 0; i < n; ++i) labels[i] = i;
  out.map = map_of_labels(labels);

  const std::vector<std::pair<int, int>> pairs =
      merge_candidates(refs.front().model, refs.front().couplings, refs.front().result, merge.strongest_exchanges, excluded);
  sum.candidates = static_cast<int>(pairs.size());
  say(fmt("node merging: %.0f candidate pairs, each merged alone (network trials, budget %.4g K)", pairs.size(), budget_K));
  std::vector<double> pair_dT(pairs.size(), 0.0);
  tbb::parallel_for(std::size_t(0), pairs.size(), [&](std::size_t k) {
    std::vector<int> l = labels;
    l[pairs[k].second] = pairs[k].first;
    const double d = merge_trial_K(refs, map_of_labels(l), solver);
    pair_dT[k] = std::isnan(d) ? std::numeric_limits<double>::infinity() : d;  // (a strict weak order below)
  });
  sum.trials = static_cast<int>(pairs.size());
  const auto within = [&](double x) { return std::count_if(pair_dT.begin(), pair_dT.end(), [x](double d) { return d <= x; }); };
  say(fmt("node merging: %.0f pairs within the budget alone, %.0f within the whole tolerance", within(budget_K),
          within(budget_K / std::max(merge.tolerance_share, 1e-9))));
  // Greedy: cheapest pair first, merged into the network of the merges accepted so far when
  // the whole network stays within the budget (the pairs' effects need not add up).
  std::vector<std::size_t> order(pairs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return pair_dT[a] < pair_dT[b]; });
  int nodes = n;
  for (std::size_t k : order) {
    if (!(pair_dT[k] <= budget_K)) break;
    const int a = labels[pairs[k].first], b = labels[pairs[k].second];
    if (a == b) continue;
    std::vector<int> l = labels;
    for (int& x : l)
      if (x == b) x = a;
    const double d = merge_trial_K(refs, map_of_labels(l), solver);
    ++sum.trials;
    if (!(d <= budget_K)) continue;
    NodeMergeStep step;
    step.first = members_named(model, labels, a);
    step.second = members_named(model, labels, b);
    step.pair_dT_K = pair_dT[k];
    step.dT_K = d;
    step.nodes_after = --nodes;
    for (int f = 0; f < model.mesh.num_faces(); ++f) {
      const int nd = model.mesh.face_node[f];
      step.faces += nd >= 0 && nd < n && l[nd] == a;
    }
    say(fmt("  merged (%.4f K alone, %.4f K with the merges so far): ", pair_dT[k], d) + model.nodes[pairs[k].first].name +
        " + " + model.nodes[pairs[k].second].name + fmt(", %.0f nodes", nodes));
    sum.steps.push_back(step);
    sum.dT_K = d;
    labels = l;
  }
  if (merge.confirm_by_tracing && !sum.steps.empty())
    labels = confirmed_by_tracing(model, refs, simulation, budget_K / std::max(merge.tolerance_share, 1e-9), sum, say);
  out.map = map_of_labels(labels);
  for (const CaseReference& r : refs) out.references.push_back(r.result);
  sum.nodes_after = out.map.num_merged();
  sum.seconds = since(t0);
  say(fmt("node merging: %.0f -> %.0f nodes, max |dT| %.4f K", n, sum.nodes_after, sum.dT_K) +
      fmt(" (%.0f trials, %.1f s)", sum.trials, sum.seconds));
  return out;
}

VerificationStatistics verify_through_node_map(const std::vector<const ThermalModel*>& originals_per_case,
                                               const std::vector<const ThermalModel*>& candidates_per_case,
                                               const ModelSimulationSettings& settings, int replicates,
                                               std::uint64_t search_seed, VerificationOriginals& originals) {
  if (originals_per_case.size() != candidates_per_case.size())
    throw InvalidInput("verification: one candidate per load case is needed");
  std::vector<VerificationCase> cases;
  for (std::size_t c = 0; c < candidates_per_case.size(); ++c)
    cases.push_back({originals_per_case[c], candidates_per_case[c], true});
  return verify_statistically(cases, settings, replicates, search_seed, &originals);
}

ReductionRun reduce_with_node_merging(const ThermalModel& model, const ReduceSettings& settings,
                                      const NodeMergeSettings& merge) {
  const double tol = settings.tolerance_K;
  if (!std::isfinite(tol) || tol <= 0)
    throw InvalidInput("tolerance must be a finite temperature difference > 0 K (got " + std::to_string(tol) + ")");
  if (!(merge.tolerance_share > 0.0 && merge.tolerance_share < 1.0))
    throw InvalidInput("the merges' share of the tolerance must lie in (0, 1)");
  auto say = [&](const std::string& s) { if (settings.progress) settings.progress(s); };
  MergeSearch ms = search_node_merges(model, settings.extra_cases, settings.reference.simulation, merge,
                                      merge.tolerance_share * tol, say);
  auto plain = [&](const std::string& why) {
    say("node merging: " + why + "; reducing the original's mesh alone");
    ReductionRun run = reduce_model(model, settings);
    ms.summary.fallback = why;
    ms.summary.nodes_after = ms.summary.nodes_before;
    ms.summary.decimation_tolerance_K = tol;
    run.merging = ms.summary;
    return run;
  };
  if (ms.map.num_merged() == static_cast<int>(model.nodes.size())) return plain("no merge within the budget");

  const ThermalModel merged = merge_nodes(model, ms.map);
  ReduceSettings inner = settings;
  inner.tolerance_K = tol;
  inner.verification_tolerance_K = tol;
  // Each original node's budget is what its merge left of it (node_budget.h): the decimation's
  // trials are measured against the original through the map, not against the merged model
  // within the tolerance less the merges' worst |dT|.
  inner.node_budget = [&](std::size_t c, const SimulationResult& merged_reference, double search_K) {
    NodeBudget b = node_budget(ms.references.at(c), merged_reference, merged.node_map, search_K);
    const Eigen::VectorXd left = search_K * b.weight.cwiseInverse().rowwise().minCoeff();  // per original node
    const auto most = std::count_if(left.data(), left.data() + left.size(), [&](double x) { return x >= 0.9 * search_K; });
    say(fmt("node budgets: search %.4g K; every original node keeps at least %.4g K, ", search_K, left.minCoeff()) +
        fmt("%.0f of %.0f keep 90 %% or more", static_cast<double>(most), static_cast<double>(left.size())));
    return b;
  };
  std::vector<ThermalModel> originals{with_case(model, own_case(model))};
  for (const LoadCase& c : settings.extra_cases) originals.push_back(with_case(model, c));
  std::vector<const ThermalModel*> original_ptrs;
  for (const ThermalModel& m : originals) original_ptrs.push_back(&m);
  VerificationOriginals kept;  // the original's runs serve every candidate
  inner.verify_candidate = [&](const std::vector<const ThermalModel*>& candidates) {
    return verify_through_node_map(original_ptrs, candidates, settings.reference.simulation,
                                   settings.verification_replicates, model.radiation.seed, kept);
  };
  say(fmt("decimating the merged model (%.0f nodes), each original node within the search tolerance less its "
          "merge's |dT|, verified against the original within %.4g K",
          ms.summary.nodes_after, tol));
  ReductionRun run;
  try {
    run = reduce_model(merged, inner);
  } catch (const Error& e) {  // the merged model's noise floor or verification: the original alone
    return plain(std::string("the merged model could not be reduced (") + e.what() + ")");
  }
  run.tolerance_K = tol;
  ms.summary.decimation_tolerance_K = inner.tolerance_K;
  ms.summary.node_map = merged.node_map;
  run.merging = ms.summary;
  return run;
}

}  // namespace thermodec
