#include "thermodec/reduction/statistical_verification.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "thermodec/common/errors.h"
#include "thermodec/common/side_by_side.h"
#include "thermodec/nodes/merge_nodes.h"
#include "thermodec/reduction/merged_network.h"

namespace thermodec {

double student_t_975(int dof) {
  if (dof < 1) throw InvalidInput("Student t quantile needs >= 1 degree of freedom");
  static const double table[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                 2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                 2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (dof <= 30) return table[dof - 1];
  const double z = 1.959964, n = dof;  // Cornish-Fisher, two terms: error < 1e-3 beyond 30
  return z + (z * z * z + z) / (4.0 * n) + (5.0 * std::pow(z, 5) + 16.0 * z * z * z + 3.0 * z) / (96.0 * n * n);
}

VerificationStatistics difference_upper_bound(const std::vector<Eigen::MatrixXd>& d) {
  const int R = static_cast<int>(d.size());
  if (R < 2) throw InvalidInput("verification needs at least 2 replicate pairs");
  for (const auto& m : d)
    if (m.rows() != d[0].rows() || m.cols() != d[0].cols())
      throw InvalidInput("verification: replicate differences differ in shape");
  Eigen::MatrixXd mean = Eigen::MatrixXd::Zero(d[0].rows(), d[0].cols());
  for (const auto& m : d) mean += m;
  mean /= R;
  Eigen::MatrixXd var = Eigen::MatrixXd::Zero(mean.rows(), mean.cols());
  for (const auto& m : d) var += (m - mean).cwiseAbs2();
  const Eigen::MatrixXd se = (var / (R - 1) / R).cwiseSqrt();
  const double t = student_t_975(R - 1);
  VerificationStatistics s;
  s.replicates = R;
  s.upper_bound_K = -1.0;
  s.max_abs_dT_K = -1.0;
  for (int j = 0; j < mean.cols(); ++j)
    for (int i = 0; i < mean.rows(); ++i) {
      const double m = std::abs(mean(i, j)), u = m + t * se(i, j);
      if (std::isnan(u)) return {NAN, NAN, NAN, kVerificationConfidence, R, {}, i, j};
      if (m > s.max_abs_dT_K) {
        s.max_abs_dT_K = m;
        s.standard_error_K = se(i, j);
      }
      if (u > s.upper_bound_K) {
        s.upper_bound_K = u;
        s.node = i;
        s.time_index = j;
      }
    }
  return s;
}

std::vector<std::uint64_t> verification_seeds(std::uint64_t search_seed, int replicates) {
  // An odd 64-bit offset (golden ratio) far from the search's seed + small integers.
  std::vector<std::uint64_t> out;
  const std::uint64_t base = search_seed + 0x9E3779B97F4A7C15ull;
  for (int k = 0; k < replicates; ++k) out.push_back(base + static_cast<std::uint64_t>(k));
  return out;
}

}  // namespace thermodec

namespace thermodec {

namespace {

// The original sampled as densely as the merged node each of its nodes is in (the reduction's
// boosts or thinning of the merged candidate), so that both sides of a pair share their budgets.
void sample_as_merged(ThermalModel& original, const ThermalModel& merged) {
  std::vector<std::string> names;
  for (const Node& nd : merged.nodes) names.push_back(nd.name);
  const std::vector<int> idx = merged_index_of_original(merged.node_map, names);
  for (std::size_t k = 0; k < merged.node_map.size() && k < original.nodes.size(); ++k)
    if (original.nodes[k].name == merged.node_map[k].first) original.nodes[k].sampling_boost = merged.nodes[idx[k]].sampling_boost;
}

}  // namespace

VerificationStatistics verify_statistically(const std::vector<VerificationCase>& cases,
                                            const ModelSimulationSettings& settings, int replicates,
                                            std::uint64_t search_seed, VerificationOriginals* originals) {
  if (replicates < 2) throw InvalidInput("verification needs at least 2 replicate pairs");
  const std::vector<std::uint64_t> seeds = verification_seeds(search_seed, replicates);
  VerificationOriginals local;
  VerificationOriginals& kept = originals ? *originals : local;
  if (kept.per_case.size() < cases.size()) kept.per_case.resize(cases.size());
  // Every run is independent of the others: the original's missing ones and the candidate's,
  // two at a time (run_side_by_side), each into its own slot; then compared in order.
  std::vector<std::vector<SimulationResult>> rb(cases.size(), std::vector<SimulationResult>(replicates));
  std::vector<std::pair<std::size_t, int>> originals_to_run;  // (case, replicate)
  for (std::size_t c = 0; c < cases.size(); ++c)
    for (int j = static_cast<int>(kept.per_case[c].size()); j < replicates; ++j) originals_to_run.emplace_back(c, j);
  const int n_orig = static_cast<int>(originals_to_run.size());
  std::vector<SimulationResult> ra_new(n_orig);  // (kept only once every run succeeded)
  const int n_cand = static_cast<int>(cases.size()) * replicates;
  run_side_by_side(n_orig + n_cand, 2, [&](int i) {
    if (i < n_orig) {
      const auto [c, j] = originals_to_run[i];
      ThermalModel a = *cases[c].original;
      if (cases[c].through_node_map) sample_as_merged(a, *cases[c].candidate);
      a.radiation.seed = seeds[j];
      ra_new[i] = simulate_model(a, settings);
      return;
    }
    const std::size_t c = static_cast<std::size_t>((i - n_orig) / replicates);
    const int j = (i - n_orig) % replicates;
    ThermalModel b = *cases[c].candidate;
    b.radiation.seed = seeds[j];
    rb[c][j] = simulate_model(b, settings);
    if (cases[c].through_node_map) rb[c][j] = result_through_node_map(rb[c][j], b.node_map);
  });
  for (int i = 0; i < n_orig; ++i) kept.per_case[originals_to_run[i].first].push_back(std::move(ra_new[i]));
  // Each case bounded alone (cases may have other times); the max over cases of the bounds
  // bounds the max over cases, by the same argument as over nodes.
  VerificationStatistics s;
  double estimate = 0.0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const std::vector<SimulationResult>& ra = kept.per_case[c];
    std::vector<Eigen::MatrixXd> d;
    for (int j = 0; j < replicates; ++j) {
      compare_results(ra[j], rb[c][j]);  // throws if nodes or times do not line up
      if (ra[j].nodes != rb[c][j].nodes)
        throw InvalidInput(cases[c].through_node_map ? "verification: the node map lists the nodes in another order"
                                                     : "verification: the candidate's nodes are in another order");
      d.push_back(rb[c][j].temperature_K - ra[j].temperature_K);
    }
    const VerificationStatistics sc = difference_upper_bound(d);
    if (!(sc.upper_bound_K <= s.upper_bound_K)) s = sc;  // NaN wins
    estimate = std::max(estimate, sc.max_abs_dT_K);
  }
  s.max_abs_dT_K = std::isnan(s.upper_bound_K) ? s.max_abs_dT_K : estimate;
  s.seeds = seeds;
  return s;
}

}  // namespace thermodec
