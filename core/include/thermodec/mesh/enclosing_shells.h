#pragma once
//! Closed parts with other geometry inside them (CAD meshes: a bus modelled as the closed outer
//! surface of its structure, with a floor, tanks or boxes inside it). A closed part is one-sided
//! and rays pass through one-sided backs, so a face inside it radiates out through its walls to
//! faces whose rays stop on the walls' fronts and never come back: the couplings of the inside
//! faces are not reciprocal by geometry. Such a part is a hollow structure: its walls radiate
//! from inside too, and the faces inside exchange with them only (bare_mesh_cleanup step 5).
#include <Eigen/Core>
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

//! Whether each edge-connected component of `F` is closed (every edge used by >= 2 faces of
//! the mesh). `component` receives face_components(F). Returns one flag per component.
std::vector<char> closed_components(const Eigen::MatrixXi& F, Eigen::VectorXi& component);

struct EnclosingShells {
  //! #F 1 = face of a closed component that has a face of another component inside it.
  std::vector<char> shell_face;
  //! #F 1 = face of another component lying (in part) inside a closed component.
  std::vector<char> enclosed_face;
  int shells = 0;  //!< closed components with something inside
};

//! Faces inside the closed components of `mesh`. A face is inside a closed component C when
//! one of four points of it (its centroid and the points at barycentric (.6, .2, .2) and
//! permutations) has a non-zero winding number with respect to C, counted as the signed
//! crossings of C by a ray in one fixed generic direction (C's triangles bucketed on a grid
//! across it); a point within `on_surface_m` of one of C's faces counts as outside (touching
//! parts, coincident walls). Deterministic: depends only on the mesh.
//! Precondition: F indexes V, `component` and `closed` as from closed_components.
EnclosingShells enclosing_shells(const Mesh& mesh, const Eigen::VectorXi& component, const std::vector<char>& closed,
                                 double on_surface_m);

}  // namespace thermodec
