#pragma once
// Private to core/src/decimation: vertices at a near contact of two nodes
// (DecimationOptions::near_contact_fraction, near_contacts.cpp).
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec::collapse {

//! Per vertex of `mesh`: 1 when the vertex lies within `fraction` x its shortest edge [m], and
//! within 1e-4 of the bounding-box diagonal, of a face of another node that does not contain it,
//! and one of its own faces is within 10 degrees of parallel to that face: two surfaces that
//! overlap at a contact (a hinge's end disc in the plane of the wall it is fixed to). Across such
//! a gap what each side sees of the other is decided at the gap's scale, so moving the vertex by
//! a fraction of an edge changes the two nodes' exchange at first order. Faces without a node
//! (face_node < 0) count as one more node. 0 everywhere when fraction <= 0.
std::vector<char> near_contact_vertices(const Mesh& mesh, double fraction);

}  // namespace thermodec::collapse
