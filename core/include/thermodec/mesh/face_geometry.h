#pragma once
//! Per-face geometry of a triangle mesh: areas, unit normals, degeneracy.
#include <Eigen/Core>
#include <vector>

namespace thermodec {

//! Area of each face [m^2 if V is in m]. V: #V x 3, F: #F x 3 (valid indices). Returns #F.
Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

//! Unit normal of each face, counter-clockwise corners seen from the front: #F x 3.
//! Degenerate faces (see is_degenerate_face) get a zero row.
Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

//! True if face f has a repeated vertex index or (numerically) zero area: twice its area is
//! at most 1e-12 times the square of its longest edge (collinear corners to double precision).
bool is_degenerate_face(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f);

//! Indices of all degenerate faces, ascending.
std::vector<int> degenerate_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace thermodec
