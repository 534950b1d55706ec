#pragma once
//! Vertex welding: merging vertices that lie within a distance tolerance of each other.
#include <Eigen/Core>

namespace thermodec {

struct WeldResult {
  Eigen::MatrixXd V;           //!< #V' x 3 welded positions (each the first input vertex of its cluster)
  Eigen::VectorXi new_index;   //!< #V: for each input vertex, its row in V
};

//! Merges vertices closer than `tolerance` (Euclidean, same units as V) into the first of
//! them in input order, using a hash grid. Deterministic: the result depends only on V's order.
//! Clusters are greedy (a vertex joins the earliest surviving vertex within tolerance), so
//! chains of near vertices are not merged transitively. tolerance = 0 merges exact duplicates.
//! \throw InvalidInput if tolerance < 0 or not finite, or V holds non-finite coordinates.
WeldResult weld_vertices(const Eigen::MatrixXd& V, double tolerance);

//! Welds V and re-indexes F in place. Unreferenced vertices are kept (welded like the others).
//! \return the number of vertices removed.
int weld_mesh_vertices(Eigen::MatrixXd& V, Eigen::MatrixXi& F, double tolerance);

}  // namespace thermodec
