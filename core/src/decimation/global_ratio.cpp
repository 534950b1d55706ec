// The paper's global-ratio rule (clusters sorted smallest first, deficits carried forward).
#include "thermodec/decimation/global_ratio.h"

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "thermodec/common/errors.h"

namespace thermodec {

Eigen::VectorXd node_ratios_for_global_ratio(const Eigen::VectorXi& face_counts_per_node,
                                             double global_ratio, int min_faces_per_node,
                                             const Eigen::VectorXd& max_ratio_per_node) {
  const int n = static_cast<int>(face_counts_per_node.size());
  if (!(global_ratio >= 0 && global_ratio < 1))
    throw InvalidInput("global reduction ratio " + std::to_string(global_ratio) + " is not in [0, 1)");
  if (max_ratio_per_node.size() != 0 && max_ratio_per_node.size() != n)
    throw InvalidInput("max_ratio_per_node has " + std::to_string(max_ratio_per_node.size()) +
                       " entries for " + std::to_string(n) + " nodes");
  for (int i = 0; i < n; ++i)
    if (face_counts_per_node[i] < 0)
      throw InvalidInput("node " + std::to_string(i) + " has a negative face count");
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return face_counts_per_node[a] < face_counts_per_node[b];
  });
  Eigen::VectorXd ratio = Eigen::VectorXd::Zero(n);
  double deficit = 0;  // faces still to remove, carried from smaller nodes
  for (int i : order) {
    const int count = face_counts_per_node[i];
    if (count == 0) continue;
    double removable = std::max(0, count - std::max(min_faces_per_node, 0));
    if (max_ratio_per_node.size() == n) removable = std::min(removable, max_ratio_per_node[i] * count);
    removable = std::max(removable, 0.0);
    const double wanted = global_ratio * count + deficit;
    const double removed = std::min(wanted, removable);
    deficit = wanted - removed;
    ratio[i] = removed / count;
  }
  return ratio;
}

}  // namespace thermodec
