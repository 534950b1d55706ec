#pragma once
//! How far merging nodes can go at all, from the original's temperatures alone.
//!
//! A merged node is isothermal: every original member is compared with its one temperature, so
//! two members whose reference temperatures differ by d at some time put one of them at least
//! d / 2 from it. Nodes pairwise farther apart than 2 tol therefore each need a merged node of
//! their own: the largest such set (a maximum clique of the graph "spread > 2 tol") bounds the
//! merged node count from below at tolerance tol, whatever the merges, the couplings or the
//! decimation. Conversely, the least tol at which that bound allows N nodes bounds from below
//! the max |dT| any merge into N nodes spends by itself. Both ignore what merging does to the
//! network (the merged node's temperature is taken as free): real merges spend more.
//! docs/reduction.md, "Merging nodes: the bound".
#include <Eigen/Core>
#include <vector>

namespace thermodec {

//! Per pair of nodes, the max over load cases and times of |T_i - T_j| [K]; `temperature_K`
//! holds one nodes x times matrix per case. Nodes listed in `never_merged` (kept or
//! fixed-temperature) get an infinite spread to every other node.
Eigen::MatrixXd pairwise_spread_K(const std::vector<Eigen::MatrixXd>& temperature_K,
                                  const std::vector<int>& never_merged = {});

//! The largest set of nodes whose pairwise spreads all exceed 2 max_dT_K (each needs its own
//! merged node), ascending. Exact (Bron-Kerbosch with pivoting) unless more than `max_calls`
//! recursive calls are needed; then the largest set found, still a valid lower bound.
std::vector<int> nodes_pairwise_apart(const Eigen::MatrixXd& spread_K, double max_dT_K, long max_calls = 2000000);

//! The least max |dT| [K] a merge of these nodes into at most `nodes` merged nodes must spend:
//! the smallest tol at which nodes_pairwise_apart holds at most `nodes` nodes (half of one of
//! the pairwise spreads; 0 when `nodes` >= the node count).
double least_merge_dT_K(const Eigen::MatrixXd& spread_K, int nodes);

}  // namespace thermodec
