#pragma once
//! The one shared triangle mesh of a thermal model. Nodes are never split into separate
//! meshes: every face carries its thermal node, its material and its sidedness, so that
//! decimation and ray tracing see interfaces between nodes as shared edges.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace thermodec {

//! Indexed triangle mesh with per-face attributes (plain data, libigl style).
struct Mesh {
  //! #V x 3 vertex positions [m] (after the model's unit_scale is applied).
  Eigen::MatrixXd V;
  //! #F x 3 vertex indices, counter-clockwise seen from the emitting (front) side.
  Eigen::MatrixXi F;
  //! #F node index per face into node_names (and ThermalModel::nodes); -1 = unassigned.
  Eigen::VectorXi face_node;
  //! #F material index per face into material_names (front side); -1 = the node's material.
  Eigen::VectorXi face_material;
  //! #F back-side material index; -1 = one-sided face (the back is inside a closed solid and
  //! neither emits nor absorbs). >= 0 = two-sided thin sheet (e.g. a solar panel) whose back
  //! radiates with that material.
  Eigen::VectorXi face_back_material;
  //! Group names (OBJ `g`/`o`) = thermal node names.
  std::vector<std::string> node_names;
  //! Material names (OBJ `usemtl`, model-file keys).
  std::vector<std::string> material_names;

  int num_vertices() const { return static_cast<int>(V.rows()); }
  int num_faces() const { return static_cast<int>(F.rows()); }
  bool is_two_sided(int f) const { return face_back_material.size() > f && face_back_material[f] >= 0; }
};

}  // namespace thermodec
