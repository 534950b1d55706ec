#pragma once
// Private to core/src/decimation: contacts a flat surface need not carry as vertices
// (DecimationOptions::release_contacts, contact_release.cpp).
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec::collapse {

//! The input mesh with its contact vertices split: where a part only touches a flat region
//! (a sheet standing on a panel along a non-manifold edge, a part touching a flat face at a
//! bow-tie vertex), the flat region's faces get their own copy of the vertex, free to collapse
//! inside the region; the touching part keeps the input vertex, frozen.
struct ContactRelease {
  Mesh mesh;                       //!< same faces (same order, node, material); more vertices
  std::vector<int> input_vertex;   //!< #V of `mesh`: the input vertex each vertex copies
  std::vector<char> keep_frozen;   //!< #V of `mesh`: the touching part's contact vertices
  int released = 0;                //!< vertex copies made
};

//! Splits the contact vertices of `mesh` (faces grouped into regions by `face_region`, one
//! entry per face). A fan of faces around a vertex is released when it is a closed disk around
//! it (every edge at the vertex shared by two faces of the fan, across a non-manifold edge by
//! the one pair of coplanar faces of one region), of one region, and flat (unit normals within
//! `flat_tolerance` of each other); when every fan around the vertex is such a disk, the first
//! keeps the input vertex. A vertex with a single fan is never split.
ContactRelease release_contacts(const Mesh& mesh, const std::vector<int>& face_region, double flat_tolerance);

}  // namespace thermodec::collapse
