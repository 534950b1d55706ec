#include "thermodec/reduction/node_budget.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "thermodec/common/errors.h"
#include "thermodec/nodes/merge_nodes.h"

namespace thermodec {

NodeBudget node_budget(const SimulationResult& original, const SimulationResult& merged,
                       const std::vector<std::pair<std::string, std::string>>& node_map, double search_tolerance_K,
                       double floor_share, bool signed_budgets) {
  const double s = search_tolerance_K;
  if (!(s > 0.0) || !std::isfinite(s)) throw InvalidInput("node budget: the search tolerance must be > 0 K");
  if (!(floor_share > 0.0 && floor_share <= 1.0)) throw InvalidInput("node budget: floor_share must lie in (0, 1]");
  if (original.temperature_K.cols() != merged.temperature_K.cols())
    throw InvalidInput("node budget: the original and merged results differ in output times");
  const Eigen::Index n = static_cast<Eigen::Index>(original.nodes.size());
  if (original.temperature_K.rows() != n) throw InvalidInput("node budget: the original result has no node names");
  // The merged node of each original node, in the original result's order.
  std::vector<std::pair<std::string, std::string>> ordered;
  for (const std::string& name : original.nodes) {
    const auto it = std::find_if(node_map.begin(), node_map.end(), [&](const auto& p) { return p.first == name; });
    if (it == node_map.end()) throw InvalidInput("node budget: original node '" + name + "' is not in the node map");
    ordered.push_back(*it);
  }
  NodeBudget b;
  b.merged_row = merged_index_of_original(ordered, merged.nodes);
  b.weight.resize(n, original.temperature_K.cols());
  b.opposite_weight.resize(n, original.temperature_K.cols());
  b.merge_dT_K.resize(n, original.temperature_K.cols());
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index m = b.merged_row[static_cast<std::size_t>(i)];
    for (Eigen::Index t = 0; t < b.weight.cols(); ++t) {
      const double signed_e = merged.temperature_K(m, t) - original.temperature_K(i, t);
      const double e = std::abs(signed_e);
      // (NaN: the floor's weight, and the trial's own NaN fails the search anyway)
      const double left = std::isnan(e) ? floor_share * s : std::max(s - e, floor_share * s);
      b.weight(i, t) = s / left;
      b.merge_dT_K(i, t) = signed_e;
      // Towards the original the node may move by |e| to reach it and by S past it.
      b.opposite_weight(i, t) = signed_budgets && !std::isnan(e) ? s / (s + e) : b.weight(i, t);
    }
  }
  return b;
}

TrialResult within_node_budget(const TrialResult& t, const NodeBudget& b) {
  const Eigen::Index rows = static_cast<Eigen::Index>(b.merged_row.size());
  if (b.weight.rows() != rows || t.dT_K.cols() != b.weight.cols() || b.opposite_weight.rows() != rows ||
      b.opposite_weight.cols() != b.weight.cols() || b.merge_dT_K.rows() != rows || b.merge_dT_K.cols() != b.weight.cols())
    throw InvalidInput("node budget: the trial's field (" + std::to_string(t.dT_K.rows()) + " x " +
                       std::to_string(t.dT_K.cols()) + ") does not match the budget (" + std::to_string(rows) + " x " +
                       std::to_string(b.weight.cols()) + ")");
  TrialResult out = t;
  out.dT_K.resize(rows, t.dT_K.cols());
  out.node_max_abs_dT_K = Eigen::VectorXd::Zero(t.dT_K.rows());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (Eigen::Index i = 0; i < rows; ++i) {
    const int m = b.merged_row[static_cast<std::size_t>(i)];
    if (m < 0 || m >= t.dT_K.rows()) throw InvalidInput("node budget: a merged row is outside the trial's field");
    for (Eigen::Index k = 0; k < t.dT_K.cols(); ++k) {
      const double d = t.dT_K(m, k);
      const bool towards = d * b.merge_dT_K(i, k) < 0.0;  // (NaN: false, the larger weight)
      out.dT_K(i, k) = d * (towards ? b.opposite_weight(i, k) : b.weight(i, k));
    }
    const Eigen::ArrayXd a = out.dT_K.row(i).transpose().array().abs();
    double& worst = out.node_max_abs_dT_K[m];
    if (a.isNaN().any()) worst = nan;  // (NaN fails every tolerance: it must not hide behind max)
    else if (a.size() > 0 && !std::isnan(worst)) worst = std::max(worst, a.maxCoeff());
  }
  out.max_abs_dT_K = out.node_max_abs_dT_K.array().isNaN().any()
                         ? nan
                         : (out.node_max_abs_dT_K.size() ? out.node_max_abs_dT_K.maxCoeff() : 0.0);
  return out;
}

}  // namespace thermodec
