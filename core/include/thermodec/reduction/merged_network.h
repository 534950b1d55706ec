#pragma once
//! A merged model's network from its original's, without tracing: a merged node's couplings
//! are the sums of its members' couplings to the rest (GR [m^2], GL [W/K]), its loads [W] the
//! sums of its members' loads, the couplings between its members dropped. With the same
//! samples this equals tracing the merged face labels: a node's coupling is already the sum
//! of its faces' Gebhart exchanges (docs/radiation.md), so summing over the merged faces is the
//! same sum, up to the reciprocity weighting of each node pair (a weighted mean of the two
//! directions). And the comparison of a merged model's temperatures with its original's,
//! node by node, through the node map.
#include <string>
#include <utility>
#include <vector>

#include "thermodec/environment/loads.h"
#include "thermodec/nodes/merge_nodes.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/thermal/simulate.h"

namespace thermodec {

//! Node couplings of the merged nodes: GR, GR to space and areas summed over the members;
//! view factors area-weighted; standard errors added in quadrature (members' errors taken as
//! independent); the diagonal holds what the members exchange among themselves (ignored by
//! the network). \throw InvalidInput if sizes disagree with the map.
NodeCouplings merge_couplings(const NodeCouplings& couplings, const NodeMergeMap& map);

//! Loads of the merged nodes: every component (and its knots) summed over the members,
//! standard errors in quadrature. \throw InvalidInput if sizes disagree with the map.
Loads merge_loads(const Loads& loads, const NodeMergeMap& map);

//! A merged model's result seen through its node map: one row per original node (in the map's
//! order, named as the original), holding its merged node's temperature and noise. Loads are
//! not split back (left empty). \throw InvalidInput if a merged name is not in the result.
SimulationResult result_through_node_map(const SimulationResult& merged,
                                         const std::vector<std::pair<std::string, std::string>>& node_map);

}  // namespace thermodec
