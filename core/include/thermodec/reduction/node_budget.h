#pragma once
//! Per-original-node budgets for the decimation of a merged model (docs/reduction.md, "Merging
//! nodes"). The verified error is the largest over ORIGINAL nodes of |T_candidate - T_original|;
//! for an original node i of merged node m it splits into the decimation's difference against
//! the merged model's reference, D_m = T_candidate(m) - T_merged(m), and the merge's own
//! difference e_i = T_merged(m) - T_original(i). A merge's e falls on a few members (those far
//! from the merged temperature); every other original node keeps almost the whole tolerance.
//! |D_m| <= S - |e_i| at every time (S: the search tolerance) bounds |D_m + e_i| by S. A trial's
//! field is read per original node and scaled by w_i(t) = S / (S - |e_i(t)|): the search then
//! meets one uniform tolerance S, and since the scaling is linear, the strategies' superposed
//! predictions (sums of single-node fields) stay what they are.
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "thermodec/reduction/trial.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec {

//! The scaling of one load case's trials (plain data).
struct NodeBudget {
  //! Per original node (row of `weight`): index of its merged node (a row of the trial).
  std::vector<int> merged_row;
  //! Original nodes x output times: S / max(S - |e_i(t)|, floor_share S), >= 1.
  Eigen::MatrixXd weight;
};

//! The budget of one case: `original` is the unmerged model's simulation, `merged` the merged
//! model's with the same seed and times, `node_map` original -> merged node names (every
//! original node of `original`, in any order), `search_tolerance_K` S > 0, `floor_share` in
//! (0, 1]: the least budget a node keeps, as a share of S (so weights stay <= 1 / floor_share).
//! \throw InvalidInput on mismatched sizes, an unmapped node or S <= 0.
NodeBudget node_budget(const SimulationResult& original, const SimulationResult& merged,
                       const std::vector<std::pair<std::string, std::string>>& node_map, double search_tolerance_K,
                       double floor_share = 0.05);

//! The trial `t` (rows: merged nodes) read per original node and scaled by `b`: dT_K has a row
//! per original node, node_max_abs_dT_K stays per merged node (the largest of its members'
//! scaled rows), max_abs_dT_K the largest of all (NaN kept). Faces and timing unchanged.
//! \throw InvalidInput if the trial's field does not match the budget's shape.
TrialResult within_node_budget(const TrialResult& t, const NodeBudget& b);

}  // namespace thermodec
