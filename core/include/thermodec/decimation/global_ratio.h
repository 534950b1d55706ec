#pragma once
//! The paper's global-ratio rule: turn one global reduction ratio into one ratio per node.
#include <Eigen/Core>

namespace thermodec {

//! Per-node reduction ratios (fraction of faces REMOVED: 0 = keep all, 0.9 = keep 10 %) that
//! together remove `global_ratio` of all faces, following the paper: nodes are visited by
//! face count, smallest first (ties by node index); each is asked to remove
//! global_ratio * faces plus the deficit carried from the nodes before it; a node that cannot
//! remove that many (it must keep at least `min_faces_per_node` faces, or its own entry of
//! `max_ratio_per_node` when given) removes what it can and carries the rest to the next one.
//! Ratios are real numbers (fractions of a face are carried, not rounded), so the sum of
//! ratio * faces equals global_ratio * total unless even the largest nodes are saturated.
//! \param face_counts_per_node #N faces per node (>= 0).
//! \param global_ratio in [0, 1).
//! \param max_ratio_per_node optional #N upper bounds in [0, 1] (e.g. what a previous
//!        decimation run could reach); empty = only the min_faces_per_node limit.
//! \return #N ratios in [0, 1).
//! \throw InvalidInput if global_ratio is outside [0, 1), a count is negative, or sizes differ.
Eigen::VectorXd node_ratios_for_global_ratio(const Eigen::VectorXi& face_counts_per_node,
                                             double global_ratio, int min_faces_per_node = 1,
                                             const Eigen::VectorXd& max_ratio_per_node = {});

}  // namespace thermodec
