#pragma once
//! Merging thermal nodes: several nodes become one isothermal node on the same shared mesh.
//! The merged node's faces keep their own materials and sidedness (a node may carry several
//! coatings); its capacitance and power are the members' sums; conductive links to the rest
//! are summed per pair, links between its members dropped. Radiative couplings need no rule
//! here: they are traced on the relabelled faces (or summed over the members' couplings, which
//! is the same sum of face-level exchanges, reduction/merged_network.h).
#include <string>
#include <vector>

#include "thermodec/nodes/thermal_model.h"

namespace thermodec {

//! Which merged node each node of a model becomes.
struct NodeMergeMap {
  //! Per node of the model merged (its order): index of its merged node.
  std::vector<int> merged_of_node;
  //! Per merged node: its members (indices into the model merged), ascending.
  std::vector<std::vector<int>> members;
  int num_merged() const { return static_cast<int>(members.size()); }
};

//! The map of `group_of_node` (per node, any integer label; nodes with equal labels merge).
//! Merged nodes are ordered by their first member, so the identity labelling keeps every node
//! in place. \throw InvalidInput if the size differs from num_nodes.
NodeMergeMap node_merge_map(const std::vector<int>& group_of_node, int num_nodes);

//! Name of a merged node: its only member's name, or the first member's name + "+" + the
//! number of other members ("panel_px+2"), made unique against `taken` with a suffix.
std::string merged_node_name(const std::vector<std::string>& member_names, const std::vector<std::string>& taken);

//! The model with the nodes of each group merged (node order: NodeMergeMap). C [J/K], Q [W]
//! summed; a merged node's default material is its first member's (every face keeps its own);
//! sampling boosts the largest of the members'; conductances [W/K] summed per merged pair (first
//! appearance order), links inside a merged node dropped. ThermalModel::node_map records
//! original -> merged names, composed with the input's own map if it has one.
//! \throw InvalidInput if a fixed-temperature node is merged with another node.
ThermalModel merge_nodes(const ThermalModel& model, const NodeMergeMap& map);

//! Indices of the nodes whose names match any of the shell patterns (fnmatch: `*`, `?`,
//! `[..]`), ascending. \throw InvalidInput naming a pattern that matches no node.
std::vector<int> nodes_matching(const ThermalModel& model, const std::vector<std::string>& patterns);

//! Per original node name of `node_map` (original -> merged), the merged node's index in
//! `merged_names`. \throw InvalidInput naming a merged name that is not among them.
std::vector<int> merged_index_of_original(const std::vector<std::pair<std::string, std::string>>& node_map,
                                          const std::vector<std::string>& merged_names);

}  // namespace thermodec
