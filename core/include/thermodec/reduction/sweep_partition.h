#pragma once
//! Which process sweeps which node when the sensitivity sweep is spread over several.
#include <Eigen/Core>
#include <vector>

namespace thermodec {

//! Owner (0 .. processes-1) of each node: the largest nodes first, each to the process with the
//! fewest faces so far (ties: the lower process). A node's sweep costs a few trials whatever
//! its size, but larger nodes reach further ratios before the cap, so faces balance better
//! than node counts. Deterministic: every process computes the same owners.
//! \throw InvalidInput if processes < 1.
std::vector<int> assign_nodes_to_processes(const Eigen::VectorXi& faces_per_node, int processes);

}  // namespace thermodec
