#pragma once
//! Combined effects of several node reductions predicted by superposition. Each single-node
//! sensitivity trial keeps its signed difference field dT_k(r) = T(node k reduced by r) -
//! T(reference) [K] over every node and output time. To first order (the network's response
//! to small changes of its couplings and loads is linear), reducing several nodes at once moves
//! the temperatures by the sum of their fields:
//!   dT(r_1, ..., r_n) ~= sum_k dT_k(r_k),
//! so differences of opposite sign cancel and coupled nodes that each spend the tolerance add
//! up, where the per-node prediction (prediction.h) sees each node alone. The fourth-power
//! radiation law makes the sum approximate; the measured trial of the combined candidate stays
//! the judge, and the report lists predicted against measured for every candidate.
#include <Eigen/Core>
#include <vector>

#include "thermodec/reduction/sensitivity.h"

namespace thermodec {

//! True if every curve carries a difference field per sample, all of one shape.
bool has_difference_fields(const std::vector<const SensitivityCurve*>& curve_of);

//! Node k's field at `ratio`: linear between the curve's samples, zero at ratio 0, the last
//! sample's field beyond the sweep [K]. A node without a curve contributes zero.
//! \pre has_difference_fields
Eigen::MatrixXd difference_field_at(const SensitivityCurve& curve, double ratio);

//! max over nodes and times of |sum_k dT_k(ratio_k)| [K]; NaN if a field holds NaN, or if
//! the curves carry no fields.
double superposed_max_abs_dT_K(const std::vector<const SensitivityCurve*>& curve_of,
                               const Eigen::VectorXd& ratio_per_node);

//! Ratios on the curves' samples whose superposed difference stays <= target_K, chosen
//! greedily: from the unreduced model, each step advances the node (one sample further on its
//! curve) that removes the most faces per kelvin of predicted increase, among the steps that
//! keep the prediction within target_K, until none does. Deterministic (ties by node index).
//! Cost: O(steps x nodes x field size), well under a second for 64 nodes.
//! \pre has_difference_fields
Eigen::VectorXd superposed_allocation(const std::vector<const SensitivityCurve*>& curve_of, int num_nodes,
                                      double target_K);

}  // namespace thermodec
