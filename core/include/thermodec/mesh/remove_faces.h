#pragma once
//! Dropping faces from a shared mesh while its per-face attributes follow.
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

//! Keeps the faces f with keep[f] != 0, in order, with their node, material and back
//! material (missing attributes become -1); vertices and name lists are unchanged.
//! Returns, for each kept face, its index in the input (to carry other per-face arrays).
//! \pre keep.size() == mesh.num_faces().
std::vector<int> remove_faces(Mesh& mesh, const std::vector<char>& keep);

}  // namespace thermodec
