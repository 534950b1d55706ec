#pragma once
//! Two-sided faces lying in one plane over other two-sided faces (CAD meshes: a panel and its
//! blanket or solar cells exported in the same plane, or a sheet exported twice with other
//! triangles). Both layers emit from the same place, and a ray meeting the overlap stops on
//! one of them by a tie rule, so the other radiates without ever being hit: its couplings are
//! not reciprocal by geometry. Where they overlap, the layers are one surface.
#include <Eigen/Core>
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

//! #F flags, 1 = keep. Among faces with two_sided[f] != 0, in order of decreasing area (lower
//! index first on ties), a face goes when 4 of its 7 sample points (those of the touching-face
//! step) lie within `distance` [m] of the plane of a parallel (|cos| > 1 - 1e-4, either
//! orientation) two-sided face kept before it, inside that face. The larger layer stays, so
//! a face never goes together with the face covering it. Deterministic.
std::vector<char> overlapping_sheet_faces(const Mesh& mesh, const Eigen::VectorXi& two_sided, double distance);

}  // namespace thermodec
