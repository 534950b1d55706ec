#include "thermodec/reduction/merge_reduction.h"
#include "thermodec/reduction/merge_bound.h"

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

// worst[i] = max(worst[i], |dT| of original node i in d); NaN wins.
void keep_worst_per_node(const TemperatureDifference& d, Eigen::VectorXd& worst) {
  for (std::size_t i = 0; i < d.per_node.size() && i < static_cast<std::size_t>(worst.size()); ++i)
    if (!(d.per_node[i].max_abs_K <= worst[i])) worst[i] = d.per_node[i].max_abs_K;
}

// Per original node (the model's order), max |dT| over times and cases of the merged network
// `map` (no tracing); NaN kept.
Eigen::VectorXd merge_trial_K(const std::vector<CaseReference>& refs, const NodeMergeMap& map,
                              const SimulationSettings& solver) {
  Eigen::VectorXd worst = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(map.merged_of_node.size()));
  for (const CaseReference& r : refs) {
    const ThermalModel merged = merge_nodes(r.model, map);
    const SimulationResult m = simulate(merged, merge_couplings(r.couplings, map), merge_loads(r.result.loads, map), solver);
    const TemperatureDifference d = compare_results(r.result, result_through_node_map(m, merged.node_map));
    keep_worst_per_node(d, worst);
  }
  return worst;
}

double largest(const Eigen::VectorXd& v) {
  if (v.array().isNaN().any()) return std::numeric_limits<double>::quiet_NaN();
  return v.size() ? v.maxCoeff() : 0.0;
}

// The merge budget of every original node [K]: small_K for a small node (few faces: its
// decimation gains little), budget_K otherwise (the joint allocation, NodeMergeSettings). A
// merged node's temperature sits near its members of most radiating area, so a small node
// merged with a large one takes most of the merge's difference on itself.
Eigen::VectorXd budgets_K(const std::vector<char>& small, double budget_K, double small_K) {
  Eigen::VectorXd b(static_cast<Eigen::Index>(small.size()));
  for (std::size_t i = 0; i < small.size(); ++i) b[static_cast<Eigen::Index>(i)] = small[i] ? small_K : budget_K;
  return b;
}

bool within_budgets(const Eigen::VectorXd& dT, const Eigen::VectorXd& budget) {
  for (Eigen::Index i = 0; i < dT.size(); ++i)
    if (!(dT[i] <= budget[i])) return false;  // NaN fails
  return true;
}

int node_index(const ThermalModel& model, const std::string& name) {
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    if (model.nodes[i].name == name) return static_cast<int>(i);
  throw InvalidInput("node merging: no node '" + name + "'");
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

// Per original node (the model's order), max |dT| over times and cases of the merged model
// traced (the reference's seed) against the reference, through the map [K]; NaN kept.
Eigen::VectorXd traced_merge_K(const std::vector<CaseReference>& refs, const NodeMergeMap& map,
                               const ModelSimulationSettings& simulation) {
  Eigen::VectorXd worst = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(map.merged_of_node.size()));
  for (const CaseReference& r : refs) {
    const ThermalModel merged = merge_nodes(r.model, map);
    const SimulationResult m = simulate_model(merged, simulation);
    const TemperatureDifference d = compare_results(r.result, result_through_node_map(m, merged.node_map));
    keep_worst_per_node(d, worst);
  }
  return worst;
}

// Keeps the longest prefix of the accepted merges whose traced model stays within `limit_K`
// (all of them when they do; k bisected otherwise, at most ~log2(merges) simulations; with
// `all_failed` the whole set is known to fail).
std::vector<int> confirmed_by_tracing(const ThermalModel& model, const std::vector<CaseReference>& refs,
                                      const ModelSimulationSettings& simulation, double limit_K, NodeMerging& sum,
                                      const std::function<void(const std::string&)>& say, bool all_failed = false) {
  std::size_t good = 0, bad = sum.steps.size() + (all_failed ? 0 : 1), k = all_failed ? bad / 2 : sum.steps.size();
  double good_dT = 0.0;
  while (k > good && k < bad) {
    const double d = largest(traced_merge_K(refs, map_of_labels(first_merges(model, sum.steps, k)), simulation));
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

// What the merge searches share (step 3).
struct MergeContext {
  const ThermalModel& model;
  const std::vector<CaseReference>& refs;
  const SimulationSettings& solver;
  const std::vector<char>& small;
  double budget_K, small_K;
  std::function<void(const std::string&)> say;
  //! n x n (row-major): original nodes that may not share a merged node (their merge broke the
  //! traced model).
  std::vector<char> banned;
  //! Every original node's merge budget [K] (budgets_K of small, budget_K, small_K).
  Eigen::VectorXd budget;

  // Whether current nodes a and b may be joined.
  bool allowed(const std::vector<int>& labels, int a, int b) const {
    const std::size_t n = labels.size();
    for (std::size_t i = 0; i < n; ++i)
      if (labels[i] == a)
        for (std::size_t j = 0; j < n; ++j)
          if (labels[j] == b && banned[i * n + j]) return false;
    return true;
  }
};

// Records the merge of current nodes a and b (labels before: `before`, after: `after`).
void record_step(const MergeContext& c, const std::vector<int>& before, const std::vector<int>& after, int a, int b,
                 double alone_K, double dT_K, NodeMerging& sum) {
  const int n = static_cast<int>(before.size());
  NodeMergeStep step;
  step.first = members_named(c.model, before, a);
  step.second = members_named(c.model, before, b);
  step.pair_dT_K = alone_K;
  step.dT_K = dT_K;
  step.nodes_after = (sum.steps.empty() ? n : sum.steps.back().nodes_after) - 1;
  for (int f = 0; f < c.model.mesh.num_faces(); ++f) {
    const int nd = c.model.mesh.face_node[f];
    step.faces += nd >= 0 && nd < n && after[nd] == a;
  }
  c.say(fmt("  merged (%.4f K alone, %.4f K with the merges so far): ", alone_K, dT_K) + step.first.front() +
        (step.first.size() > 1 ? "+" + std::to_string(step.first.size() - 1) : std::string()) + " + " + step.second.front() +
        (step.second.size() > 1 ? "+" + std::to_string(step.second.size() - 1) : std::string()) +
        fmt(", %.0f nodes", step.nodes_after));
  sum.steps.push_back(step);
  sum.dT_K = dT_K;
}

std::vector<int> joined(std::vector<int> labels, int a, int b) {
  for (int& x : labels)
    if (x == b) x = a;
  return labels;
}

// Greedy by pairs: every candidate pair is tried alone; then, cheapest first, each is merged
// into the network of the merges accepted so far when every original node stays within its
// merged node's budget (the pairs' effects need not add up).
void merge_cheapest_pairs_first(const MergeContext& c, const std::vector<std::pair<int, int>>& pairs,
                                std::vector<int>& labels, NodeMerging& sum) {
  std::vector<double> pair_dT(pairs.size(), 0.0);
  tbb::parallel_for(std::size_t(0), pairs.size(), [&](std::size_t k) {
    const double d = largest(merge_trial_K(c.refs, map_of_labels(joined(labels, pairs[k].first, pairs[k].second)), c.solver));
    pair_dT[k] = std::isnan(d) ? std::numeric_limits<double>::infinity() : d;  // (a strict weak order below)
  });
  sum.trials += static_cast<int>(pairs.size());
  std::vector<std::size_t> order(pairs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return pair_dT[a] < pair_dT[b]; });
  for (std::size_t k : order) {
    if (!(pair_dT[k] <= c.small_K)) break;
    const int a = labels[pairs[k].first], b = labels[pairs[k].second];
    if (a == b || !c.allowed(labels, a, b)) continue;
    const std::vector<int> l = joined(labels, a, b);
    const Eigen::VectorXd dT = merge_trial_K(c.refs, map_of_labels(l), c.solver);
    ++sum.trials;
    if (!within_budgets(dT, c.budget)) continue;
    record_step(c, labels, l, a, b, pair_dT[k], largest(dT), sum);
    labels = l;
  }
}

// Max over cases and times of the spread (max - min) of the reference temperatures of the
// original nodes labelled a or b [K]: a merged node cannot keep every member within half of it.
double spread_K(const std::vector<CaseReference>& refs, const std::vector<int>& labels, int a, int b) {
  double worst = 0.0;
  for (const CaseReference& r : refs) {
    const Eigen::MatrixXd& t = r.result.temperature_K;
    Eigen::RowVectorXd lo = Eigen::RowVectorXd::Constant(t.cols(), std::numeric_limits<double>::infinity());
    Eigen::RowVectorXd hi = -lo;
    for (std::size_t i = 0; i < labels.size(); ++i)
      if (labels[i] == a || labels[i] == b) {
        lo = lo.cwiseMin(t.row(static_cast<Eigen::Index>(i)));
        hi = hi.cwiseMax(t.row(static_cast<Eigen::Index>(i)));
      }
    worst = std::max(worst, (hi - lo).maxCoeff());
  }
  return worst;
}

// Best first: every round, each pair of current nodes joined by a candidate pair (and whose
// members' reference temperatures spread by at most twice the larger budget) is tried with the
// merges so far; of those keeping every original node within its merged node's budget, the one
// of least |dT| on its own members is merged. Rounds end when no join fits.
void merge_best_first(const MergeContext& c, const std::vector<std::pair<int, int>>& pairs, std::vector<int>& labels,
                      NodeMerging& sum) {
  const double inf = std::numeric_limits<double>::infinity();
  for (;;) {
    std::vector<std::pair<int, int>> joins;
    for (const auto& [i, j] : pairs) {
      const int a = labels[i], b = labels[j];
      if (a != b) joins.emplace_back(std::min(a, b), std::max(a, b));
    }
    std::sort(joins.begin(), joins.end());
    joins.erase(std::unique(joins.begin(), joins.end()), joins.end());
    joins.erase(std::remove_if(joins.begin(), joins.end(),
                               [&](const auto& p) {
                                 return spread_K(c.refs, labels, p.first, p.second) > 2.0 * c.small_K ||
                                        !c.allowed(labels, p.first, p.second);
                               }),
                joins.end());
    std::vector<double> own(joins.size(), inf), all(joins.size(), inf);
    tbb::parallel_for(std::size_t(0), joins.size(), [&](std::size_t k) {
      const auto [a, b] = joins[k];
      const std::vector<int> l = joined(labels, a, b);
      const Eigen::VectorXd dT = merge_trial_K(c.refs, map_of_labels(l), c.solver);
      if (!within_budgets(dT, c.budget)) return;
      double worst = 0.0;
      for (std::size_t i = 0; i < l.size(); ++i)
        if (l[i] == a) worst = std::max(worst, dT[static_cast<Eigen::Index>(i)]);
      own[k] = worst;
      all[k] = largest(dT);
    });
    sum.trials += static_cast<int>(joins.size());
    const auto best = std::min_element(own.begin(), own.end());
    if (best == own.end() || !(*best < inf)) return;
    const std::size_t k = static_cast<std::size_t>(best - own.begin());
    const auto [a, b] = joins[k];
    const std::vector<int> l = joined(labels, a, b);
    // The two merged alone (from the unmerged network), for the report.
    std::vector<int> alone(labels.size());
    for (std::size_t i = 0; i < alone.size(); ++i) alone[i] = labels[i] == a || labels[i] == b ? a : static_cast<int>(i);
    const double alone_K = largest(merge_trial_K(c.refs, map_of_labels(alone), c.solver));
    ++sum.trials;
    record_step(c, labels, l, a, b, alone_K, all[k], sum);
    labels = l;
  }
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

std::vector<char> small_nodes(const ThermalModel& model, double share) {
  const int n = static_cast<int>(model.nodes.size());
  std::vector<long> faces(n, 0);
  long total = 0;
  for (int f = 0; f < model.mesh.num_faces(); ++f) {
    const int nd = model.mesh.face_node[f];
    if (nd >= 0 && nd < n) ++faces[nd], ++total;
  }
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return faces[a] < faces[b]; });
  std::vector<char> small(n, 0);
  long sum = 0;
  for (int i : order) {
    if (static_cast<double>(sum + faces[i]) > share * static_cast<double>(total)) break;
    sum += faces[i];
    small[i] = 1;
  }
  return small;
}

// What no merge can beat, from the original's temperatures (reduction/merge_bound.h): the
// fewest merged nodes at the budget and at the tolerance, and the least max |dT| a merge into
// 90 ... 25 % of the nodes spends by itself.
// `spread`: pairwise_spread_K of the references, kept and fixed nodes apart from all.
void merge_bounds(const std::vector<CaseReference>& refs, const Eigen::MatrixXd& spread, double budget_K,
                  double tolerance_K, NodeMerging& sum, const std::function<void(const std::string&)>& say) {
  const int n = static_cast<int>(spread.rows());
  sum.fewest_nodes_at_budget = static_cast<int>(nodes_pairwise_apart(spread, budget_K).size());
  const std::vector<int> apart = nodes_pairwise_apart(spread, tolerance_K);
  sum.fewest_nodes_at_tolerance = static_cast<int>(apart.size());
  for (int i : apart) sum.apart_at_tolerance.push_back(refs.front().model.nodes[i].name);
  std::string curve;
  for (double f : {0.9, 0.75, 0.6, 0.5, 0.4, 0.3, 0.25}) {
    const int nodes = std::max(1, static_cast<int>(std::floor(f * n)));
    if (!sum.least_merge_dT_K.empty() && sum.least_merge_dT_K.back().first == nodes) continue;
    sum.least_merge_dT_K.emplace_back(nodes, least_merge_dT_K(spread, nodes));
    curve += fmt(" %.0f nodes %.3g K,", nodes, sum.least_merge_dT_K.back().second);
  }
  curve.pop_back();
  say(fmt("node merging: no merge goes below %.0f nodes within the budget (%.4g K), ", sum.fewest_nodes_at_budget, budget_K) +
      fmt("%.0f within the tolerance (%.4g K); merging alone spends at least:", sum.fewest_nodes_at_tolerance, tolerance_K) +
      curve);
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
  const double tolerance_K = budget_K / std::max(merge.tolerance_share, 1e-9);
  const double small_K = std::max(budget_K, merge.small_node_share * tolerance_K);
  const std::vector<char> small = small_nodes(model, merge.small_faces_share);
  sum.small_budget_K = small_K;
  sum.small_nodes = static_cast<int>(std::count(small.begin(), small.end(), 1));
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
  // Per pair of nodes, the max over cases and times of |T_i - T_j| (kept and fixed nodes: infinite).
  std::vector<Eigen::MatrixXd> temperatures;
  for (const CaseReference& r : refs) temperatures.push_back(r.result.temperature_K);
  const Eigen::MatrixXd spread = pairwise_spread_K(temperatures, excluded);
  merge_bounds(refs, spread, budget_K, tolerance_K, sum, say);
  std::vector<int> labels(n);
  std::vector<std::pair<int, int>> pairs =
      merge_candidates(refs.front().model, refs.front().couplings, refs.front().result, merge.strongest_exchanges, excluded);
  // Every two nodes whose reference temperatures stay within twice the larger budget of each
  // other in every case (near-isothermal wherever they are: what a merge can afford).
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (spread(i, j) <= 2.0 * small_K) pairs.emplace_back(i, j);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  sum.candidates = static_cast<int>(pairs.size());
  say(fmt("node merging: %.0f candidate pairs (network trials, budget %.4g K, ", pairs.size(), budget_K) +
      fmt("%.4g K for the %.0f small nodes)", small_K, sum.small_nodes));
  MergeContext ctx{model, refs, simulation.solver, small, budget_K, small_K, say, std::vector<char>(std::size_t(n) * n, 0),
                   budgets_K(small, budget_K, small_K)};
  // The merges found are traced (the merged model simulated with the reference's seed: the
  // network trials take the original's combined couplings as exact, docs/reduction.md). When
  // that exceeds the tolerance, the last merge of the worst original node's merged node (or,
  // for a node left alone, the first merge the bisection finds failing) is banned, its two
  // sides never again in one merged node, and the search runs again; the last round keeps the
  // longest prefix that traces within the tolerance. The round keeping the fewest nodes wins.
  std::vector<int> best_labels(n);
  for (int i = 0; i < n; ++i) best_labels[i] = i;
  std::vector<NodeMergeStep> best_steps;
  double best_dT = 0.0, best_traced = 0.0;
  const int rounds = merge.confirm_by_tracing ? std::max(1, merge.tracing_rounds) : 1;
  for (int round = 0; round < rounds; ++round) {
    for (int i = 0; i < n; ++i) labels[i] = i;
    sum.steps.clear();
    sum.dT_K = sum.traced_dT_K = 0.0;
    if (merge.best_first) merge_best_first(ctx, pairs, labels, sum);
    else merge_cheapest_pairs_first(ctx, pairs, labels, sum);
    const std::vector<NodeMergeStep> found = sum.steps;
    std::size_t bad = found.size();  // the merge to ban (none)
    if (merge.confirm_by_tracing && !found.empty()) {
      const Eigen::VectorXd traced = traced_merge_K(refs, map_of_labels(labels), simulation);
      ++sum.traced_simulations;
      sum.traced_dT_K = largest(traced);
      say(fmt("node merging: %.0f merges traced: max |dT| %.4f K (limit %.4g K)", found.size(), sum.traced_dT_K,
              tolerance_K));
      if (!(sum.traced_dT_K <= tolerance_K)) {
        Eigen::Index worst = 0;
        for (Eigen::Index i = 0; i < traced.size(); ++i)
          if (std::isnan(traced[i]) || traced[i] > traced[worst]) worst = i;
        for (std::size_t k = found.size(); k-- > 0 && bad == found.size();)
          for (const auto* side : {&found[k].first, &found[k].second})
            if (std::find(side->begin(), side->end(), model.nodes[worst].name) != side->end()) bad = k;
        if (bad == found.size() || round + 1 == rounds) {
          labels = confirmed_by_tracing(model, refs, simulation, tolerance_K, sum, say, true);
          if (sum.steps.size() < found.size()) bad = sum.steps.size();
        } else {
          sum.steps.clear();  // nothing of this round is kept
        }
      }
    }
    if (sum.steps.size() > best_steps.size())
      best_labels = labels, best_steps = sum.steps, best_dT = sum.dT_K, best_traced = sum.traced_dT_K;
    if (bad == found.size() || round + 1 == rounds) break;
    say("node merging: " + found[bad].first.front() + " + " + found[bad].second.front() +
        " breaks the traced model; those members stay apart, searching again");
    for (const std::string& a : found[bad].first)
      for (const std::string& b : found[bad].second) {
        const int i = node_index(model, a), j = node_index(model, b);
        ctx.banned[std::size_t(i) * n + j] = ctx.banned[std::size_t(j) * n + i] = 1;
      }
  }
  labels = best_labels;
  sum.steps = best_steps;
  sum.dT_K = best_dT;
  sum.traced_dT_K = best_traced;
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
  if (!(merge.tolerance_share > 0.0 && merge.tolerance_share < 1.0) ||
      !(merge.small_node_share > 0.0 && merge.small_node_share < 1.0))
    throw InvalidInput("the merges' shares of the tolerance must lie in (0, 1)");
  if (!(merge.small_faces_share >= 0.0 && merge.small_faces_share < 1.0))
    throw InvalidInput("the small nodes' share of the faces must lie in [0, 1)");
  auto say = [&](const std::string& s) { if (settings.progress) settings.progress(s); };
  MergeSearch ms = search_node_merges(model, settings.extra_cases, settings.reference.simulation, merge,
                                      merge.tolerance_share * tol, say);
  auto plain = [&](const std::string& why) {
    say("node merging: " + why + "; reducing the original's mesh alone");
    ReductionRun run = reduce_model(model, settings);
    NodeMerging summary = ms.summary;
    summary.fallback = why;
    summary.nodes_after = summary.nodes_before;
    summary.decimation_tolerance_K = tol;
    run.merging = summary;
    return run;
  };
  if (ms.map.num_merged() == static_cast<int>(model.nodes.size())) return plain("no merge within the budget");

  const ThermalModel merged = merge_nodes(model, ms.map);
  ReduceSettings inner = settings;
  inner.tolerance_K = tol;
  inner.back_off_verifications = merge.back_off_verifications;
  inner.verification_tolerance_K = tol;
  // Each original node's budget is what its merge left of it (node_budget.h): the decimation's
  // trials are measured against the original through the map, not against the merged model
  // within the tolerance less the merges' worst |dT|.
  inner.node_budget = [&](std::size_t c, const SimulationResult& merged_reference, double search_K) {
    NodeBudget b = node_budget(ms.references.at(c), merged_reference, merged.node_map, search_K, 0.05,
                               merge.signed_budgets);
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
  // Verified only undecimated or backed off: the plain decimation may keep less (NPP_16: 34 of
  // 64 nodes with every face against 64 nodes with 29 % of them), never when the merged model
  // keeps a share <= 1 (the plain decimation keeps every node: 1 + its faces' share).
  const int n = static_cast<int>(model.nodes.size()), m = ms.summary.nodes_after;
  const double merged_share = kept_share(n, m, run.faces_before, run.faces_after);
  const bool backed_off = !run.outcome.history.empty() && run.outcome.history.back().action.rfind("back off", 0) == 0;
  if (merged_share <= 1.0 || (run.faces_after < run.faces_before && !backed_off)) return run;
  ReductionRun alone = plain(fmt("the merged model (%.0f nodes) verified ", m) +
                             (backed_off ? "only backed off" : "only undecimated"));
  const double plain_share = kept_share(n, n, alone.faces_before, alone.faces_after);
  say(fmt("node merging: kept share (nodes + faces) %.3f merged, %.3f decimated without merging", merged_share,
          plain_share));
  return plain_share < merged_share ? alone : run;
}

double kept_share(int nodes_before, int nodes_after, int faces_before, int faces_after) {
  return static_cast<double>(nodes_after) / std::max(nodes_before, 1) +
         static_cast<double>(faces_after) / std::max(faces_before, 1);
}

}  // namespace thermodec
