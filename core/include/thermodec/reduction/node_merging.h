#pragma once
//! What merging nodes before the decimation did (plain data, for report.json and the summary):
//! reduction/merge_reduction.h fills it.
#include <string>
#include <utility>
#include <vector>

namespace thermodec {

//! One accepted merge of the greedy search: two current nodes (each listed by its original
//! members) became one.
struct NodeMergeStep {
  std::vector<std::string> first, second;  //!< original nodes of the two merged nodes
  double pair_dT_K = 0.0;   //!< max |dT| of the two merged alone, from the unmerged network
  double dT_K = 0.0;        //!< max |dT| of every merge so far, this one included (what was accepted)
  int nodes_after = 0;      //!< nodes of the network after this merge
  int faces = 0;            //!< faces of the merged node (before decimation)
};

struct NodeMerging {
  int nodes_before = 0, nodes_after = 0;
  std::vector<std::string> kept;        //!< nodes never merged: --keep-node matches and fixed-temperature nodes
  int candidates = 0;                   //!< candidate pairs (neighbours sharing an edge, strongest exchanges)
  int trials = 0;                       //!< network trials (single merges and greedy steps)
  double budget_K = 0.0;                //!< the share of the tolerance the merges may spend [K]
  //! What a merged node of small nodes only may spend [K] (= budget_K: no such allocation), and
  //! how many original nodes are small (few faces: their decimation gains little).
  double small_budget_K = 0.0;
  int small_nodes = 0;
  double dT_K = 0.0;                    //!< measured max |dT| of all merges together (every case) [K]
  //! What the decimation of the merged model searched within [K]: the whole tolerance, each
  //! original node less its merge's own |dT| (reduction/node_budget.h).
  double decimation_tolerance_K = 0.0;
  //! The merges kept re-traced (the merged model simulated with the reference's seed): its max
  //! |dT| against the reference through the map [K] (0: not traced), and the simulations that took.
  double traced_dT_K = 0.0;
  int traced_simulations = 0;
  //! What no merge can beat (reduction/merge_bound.h): the fewest merged nodes at the merge
  //! budget and at the whole tolerance (nodes pairwise farther apart than twice it, names of
  //! the latter set), and per node count, the least max |dT| a merge into that many must spend [K].
  int fewest_nodes_at_budget = 0, fewest_nodes_at_tolerance = 0;
  std::vector<std::string> apart_at_tolerance;
  std::vector<std::pair<int, double>> least_merge_dT_K;
  std::vector<NodeMergeStep> steps;     //!< accepted merges, in order
  std::vector<std::pair<std::string, std::string>> node_map;  //!< original -> merged node
  double seconds = 0.0;                 //!< reference simulations and merge trials [s]
  //! Why the merged model was given up for a plain decimation of the original (empty: it was not).
  std::string fallback;
};

}  // namespace thermodec
