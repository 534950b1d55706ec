#pragma once
//! Topology and per-node statistics of a mesh, as printed by `thermodec info`.
#include <Eigen/Core>
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec {

//! Connected components of faces linked through shared edges (as MeshLab counts them: two
//! parts touching at a single vertex are two components). Components are numbered 0.. in
//! order of their lowest face index.
//! \param F #F x 3 vertex indices.  \return #F component id per face.
Eigen::VectorXi face_components(const Eigen::MatrixXi& F);

struct MeshStats {
  int faces = 0;
  int vertices = 0;
  int unreferenced_vertices = 0;  //!< vertices no face uses
  int edges = 0;                  //!< distinct undirected edges
  int components = 0;             //!< edge-connected face components
  int boundary_edges = 0;         //!< edges used by exactly one face (holes, open sheets)
  int non_manifold_edges = 0;     //!< edges used by three or more faces
  int degenerate_faces = 0;       //!< see is_degenerate_face
  double area_m2 = 0.0;           //!< total face area [m^2, if V is in m]
};

//! Counts of the whole mesh. Precondition: F indexes V.
MeshStats mesh_stats(const Mesh& mesh);

//! Faces per node: #node_names entries (faces with face_node -1 are not counted).
std::vector<int> node_face_counts(const Mesh& mesh);

//! Area per node [m^2]: #node_names entries, summed in face order (deterministic).
std::vector<double> node_areas_m2(const Mesh& mesh);

//! Distinct front materials (indices into material_names, ascending; -1 if some face has
//! none) used by each node's faces: #node_names entries.
std::vector<std::vector<int>> node_materials(const Mesh& mesh);

}  // namespace thermodec
