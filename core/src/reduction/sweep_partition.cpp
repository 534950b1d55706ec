#include "thermodec/reduction/sweep_partition.h"

#include <algorithm>
#include <numeric>

#include "thermodec/common/errors.h"

namespace thermodec {

std::vector<int> assign_nodes_to_processes(const Eigen::VectorXi& faces_per_node, int processes) {
  if (processes < 1) throw InvalidInput("the sweep needs at least one process (got " + std::to_string(processes) + ")");
  const int n = static_cast<int>(faces_per_node.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return faces_per_node[a] > faces_per_node[b]; });
  std::vector<long long> load(processes, 0);
  std::vector<int> owner(n, 0);
  for (int k : order) {
    const int p = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    owner[k] = p;
    load[p] += std::max(1, faces_per_node[k]);
  }
  return owner;
}

}  // namespace thermodec
