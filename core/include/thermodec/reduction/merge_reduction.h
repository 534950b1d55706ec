#pragma once
//! Reducing the network as well as the mesh: merge thermal nodes, then decimate the merged
//! model, under one verified temperature tolerance (docs/reduction.md, "Merging nodes").
//!
//! 1. The original is simulated once per load case; its node couplings and loads are kept.
//! 2. Candidates: pairs of nodes that share a mesh edge, each node's strongest exchanges
//!    (GL + 4 sigma T^3 GR) and the nodes closest to it in temperature; never a kept node
//!    (NodeMergeSettings::keep) or a fixed-temperature node.
//! 3. Every candidate is tried alone; then, cheapest first, each is merged into the network of
//!    the merges accepted so far when that network still stays within the merge budget. A trial
//!    is a network solve with the reference's own couplings and loads summed over the merged
//!    nodes (reduction/merged_network.h: correlated sampling, no tracing), compared node by
//!    node with the reference through the merge map, the largest |dT| over all nodes, times and
//!    load cases.
//! 4. The merged model is reduced by reduce_model() with per-original-node budgets
//!    (reduction/node_budget.h): each original node may take what its merge left of the search
//!    tolerance, the merge's own difference measured by the merged model's reference against the
//!    original's (same seed); its candidates are verified against the original through the node
//!    map (fresh seeds, the same statistics as reduce_model's verification) within the whole
//!    tolerance.
#include <string>
#include <vector>

#include "thermodec/nodes/merge_nodes.h"
#include "thermodec/reduction/merged_network.h"
#include "thermodec/reduction/reduce_model.h"

namespace thermodec {

struct NodeMergeSettings {
  //! Node name patterns (fnmatch) never merged; each must match a node.
  std::vector<std::string> keep;
  //! Share of the tolerance the merges may spend (their measured max |dT|); each original node
  //! leaves the decimation the search tolerance less its own merge's |dT| (node_budget.h).
  //! 0.6 (docs/benchmarks.md, "Merging nodes"): against 0.4, NPP_16 34 nodes and 1160 faces
  //! instead of 43 and 1191; 0.8 leaves the merged members no budget.
  double tolerance_share = 0.6;
  //! Joint allocation: *small* original nodes (below) may take this share of the tolerance
  //! from the merges instead. A small node has few faces, so its decimation gains little: it
  //! gives its budget to the merges. Off when <= tolerance_share (the default): at 0.85 NPP_16
  //! merges to 31 nodes, but its merged members keep 0.025 K, the decimation stops at 1400 faces
  //! and the verification rejects it (0.497 +- 0.005 K, bound 0.512 K: docs/benchmarks.md).
  double small_node_share = 0.6;
  //! The small nodes: the fewest-faced original nodes (ties by index) holding together at most
  //! this share of the model's faces [0, 1).
  double small_faces_share = 0.1;
  //! Per node, its this many strongest exchanges and this many nodes closest in temperature are
  //! candidates besides its edge neighbours.
  int strongest_exchanges = 3;
  //! The accepted merges are re-traced (the merged model simulated with the reference's seed);
  //! while that exceeds the whole tolerance (budget / tolerance_share), only the first k merges
  //! are kept, k bisected (the network trials take the original's combined couplings as exact,
  //! which a rarely hit node's reciprocity weighting can break: docs/reduction.md).
  bool confirm_by_tracing = true;
  //! Best first (every round, every join of two current nodes tried with the merges so far, the
  //! least costly merged) instead of the single pairs' cheapest first.
  bool best_first = true;
  //! When the traced model refuses the merges, the one to blame (the last merge of the worst
  //! node's merged node, else the first failing one by bisection) has its two sides kept apart
  //! and the search runs again, up to this many searches in all (the fewest nodes kept wins).
  int tracing_rounds = 6;
  //! The decimation's per-node budgets know the sign of each merge's difference: a member may
  //! move towards its original temperature by its merge's |dT| plus the tolerance, and away from
  //! it by the tolerance less that (node_budget.h). Off by default: NPP_16 at the defaults then
  //! decimates to 1031-1046 faces in the search, but the verification rejects every candidate
  //! (0.492-0.507 K: a difference cancelling the merge's at the search's seed does not under
  //! fresh seeds) and keeps the merged model undecimated; Juno at --merge-share 0.85 gains
  //! (25 nodes, 44.6 % of the faces verified; docs/benchmarks.md, "Merging nodes").
  bool signed_budgets = false;
  //! When every decimated candidate of the merged model is rejected, at most this many more
  //! verifications back the least rejected one off towards the merged model undecimated
  //! (ReduceSettings::back_off_verifications). Should the merged model end undecimated or
  //! backed off with a kept_share over 1, the original is also decimated without merging, and
  //! the result of the smaller kept_share is returned.
  int back_off_verifications = 2;
};

//! What a reduced model keeps of the original: nodes_after / nodes_before + faces_after /
//! faces_before (the two goals weighed alike; 2 = nothing reduced).
double kept_share(int nodes_before, int nodes_after, int faces_before, int faces_after);

//! Candidate pairs (i < j), ascending: nodes sharing a mesh edge, each node's `strongest`
//! largest couplings GL_ij + 4 sigma T^3 GR_ij (T: the mean of the two nodes' mean reference
//! temperatures [K]) and its `strongest` nodes of least max_t |T_i - T_j| in the reference,
//! without the nodes in `excluded`.
std::vector<std::pair<int, int>> merge_candidates(const ThermalModel& model, const NodeCouplings& couplings,
                                                  const SimulationResult& reference, int strongest,
                                                  const std::vector<int>& excluded);

//! Flags of the small nodes of `model` (NodeMergeSettings::small_faces_share): the fewest-faced
//! nodes, ascending by faces then index, while their faces together stay <= share x all faces.
std::vector<char> small_nodes(const ThermalModel& model, double share);

//! Result of the greedy merge search (step 3).
struct MergeSearch {
  NodeMergeMap map;
  NodeMerging summary;  //!< steps, candidates, trials, dT_K, budget_K, kept
  //! The original simulated once per case (its own case first, then extra_cases), with the
  //! model's seed: the baseline of the decimation's per-node budgets (node_budget.h).
  std::vector<SimulationResult> references;
};

//! Steps 1-3: the merges of `model` within budget_K [K] over its own case and `extra_cases`;
//! merged nodes of small nodes only within budget_K x small_node_share / tolerance_share.
//! \throw InvalidInput if a keep pattern matches no node.
MergeSearch search_node_merges(const ThermalModel& model, const std::vector<LoadCase>& extra_cases,
                               const ModelSimulationSettings& simulation, const NodeMergeSettings& merge,
                               double budget_K, const std::function<void(const std::string&)>& say = {});

//! Steps 1-4. The returned run is reduce_model()'s on the merged model, with `merging` set,
//! tolerance_K the whole tolerance and verification against the original; run.reduced.model
//! carries the node map. Without any accepted merge, or when the merged model cannot be
//! verified, the original is reduced as reduce_model(model, settings) does (merging.fallback
//! says why); likewise when the merged model verifies only undecimated or backed off and the
//! plain decimation keeps a smaller kept_share. \throw InvalidInput / SolverError as reduce_model.
ReductionRun reduce_with_node_merging(const ThermalModel& model, const ReduceSettings& settings,
                                      const NodeMergeSettings& merge);

//! Statistical verification (reduction/statistical_verification.h) of merged candidates
//! (one per case) against the unmerged originals through each candidate's node_map; the
//! originals' runs are kept in `originals` for later candidates.
VerificationStatistics verify_through_node_map(const std::vector<const ThermalModel*>& originals_per_case,
                                               const std::vector<const ThermalModel*>& candidates_per_case,
                                               const ModelSimulationSettings& settings, int replicates,
                                               std::uint64_t search_seed, VerificationOriginals& originals);

}  // namespace thermodec
