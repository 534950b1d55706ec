#pragma once
//! Automatic nodal breakdown for meshes without groups (STL, scans): connected components,
//! then near-planar regions by normal deviation, small regions merged into neighbours, a cap
//! on the node count. Deterministic; every face gets a node.
#include "thermodec/mesh/mesh.h"

namespace thermodec {

struct AutomaticNodeOptions {
  double max_normal_deviation_deg = 30.0;  //!< region growing: max angle to the region's seed normal
  double min_node_area_fraction = 0.002;   //!< regions smaller than this share of total area merge
  int max_nodes = 64;                      //!< cap; smallest regions merge first
};

//! Overwrites mesh.face_node and mesh.node_names ("node_000", ...).
//! \throw InvalidInput on an empty mesh or max_nodes < 1.
void assign_automatic_nodes(Mesh& mesh, const AutomaticNodeOptions& options = {});

}  // namespace thermodec
