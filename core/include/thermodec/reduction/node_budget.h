#pragma once
//! Per-original-node budgets for the decimation of a merged model (docs/reduction.md, "Merging
//! nodes"). The verified error is the largest over ORIGINAL nodes of |T_candidate - T_original|;
//! for an original node i of merged node m it splits into the decimation's difference against
//! the merged model's reference, D_m = T_candidate(m) - T_merged(m), and the merge's own
//! difference e_i = T_merged(m) - T_original(i). A merge's e falls on a few members (those far
//! from the merged temperature); every other original node keeps almost the whole tolerance.
//! |D_m + e_i| <= S (S: the search tolerance) at every time is what the verification asks. It
//! holds when D_m moves the node away from the original (the sign of e_i) by at most S - |e_i|,
//! or towards it and past it by at most S + |e_i|. A trial's field is read per original node and
//! scaled by w_i(t) = S / (S - |e_i(t)|) where D_m has the sign of e_i, and by
//! S / (S + |e_i(t)|) where it has the other sign (signed budgets): the search then meets one
//! uniform tolerance S. The scaling is linear on each side of zero, so the strategies' superposed
//! predictions (sums of single-node fields) are exact where the summed fields share a sign and
//! approximate where they cancel; every candidate is measured and verified anyway.
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
  //! Original nodes x output times: S / max(S - |e_i(t)|, floor_share S), >= 1: the weight of
  //! a trial's difference of the same sign as e_i(t) (away from the original).
  Eigen::MatrixXd weight;
  //! The weight of a difference of the other sign (towards the original): S / (S + |e_i(t)|),
  //! <= 1, with signed budgets; equal to `weight` without.
  Eigen::MatrixXd opposite_weight;
  //! e_i(t) = T_merged(m, t) - T_original(i, t) [K] (NaN kept).
  Eigen::MatrixXd merge_dT_K;
};

//! The budget of one case: `original` is the unmerged model's simulation, `merged` the merged
//! model's with the same seed and times, `node_map` original -> merged node names (every
//! original node of `original`, in any order), `search_tolerance_K` S > 0, `floor_share` in
//! (0, 1]: the least budget a node keeps, as a share of S (so weights stay <= 1 / floor_share);
//! `signed_budgets` false charges a difference towards the original as one away from it.
//! (reduce_with_node_merging passes NodeMergeSettings::signed_budgets, off by default.)
//! \throw InvalidInput on mismatched sizes, an unmapped node or S <= 0.
NodeBudget node_budget(const SimulationResult& original, const SimulationResult& merged,
                       const std::vector<std::pair<std::string, std::string>>& node_map, double search_tolerance_K,
                       double floor_share = 0.05, bool signed_budgets = false);

//! The trial `t` (rows: merged nodes) read per original node and scaled by `b` (each entry by
//! the weight of its sign against the merge's difference there): dT_K has a row
//! per original node, node_max_abs_dT_K stays per merged node (the largest of its members'
//! scaled rows), max_abs_dT_K the largest of all (NaN kept). Faces and timing unchanged.
//! \throw InvalidInput if the trial's field does not match the budget's shape.
TrialResult within_node_budget(const TrialResult& t, const NodeBudget& b);

}  // namespace thermodec
