#pragma once
// Hand-built meshes and models for the environment and thermal tests (no files needed).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "thermodec/nodes/thermal_model.h"

namespace thermodec::testing {

//! Appends a quad (corners counter-clockwise seen from its front) split in n x n x 2 triangles.
inline void add_quad(Mesh& m, const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& v, int node,
                     int material, int back_material = -1, int n = 1) {
  const int v0 = m.num_vertices();
  m.V.conservativeResize(v0 + (n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.V.row(v0 + j * (n + 1) + i) = (o + u * (double(i) / n) + v * (double(j) / n)).transpose();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = v0 + j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      for (const Eigen::Vector3i& t : {Eigen::Vector3i(a, b, c), Eigen::Vector3i(a, c, d)}) {
        const int f = m.num_faces();
        m.F.conservativeResize(f + 1, 3);
        m.F.row(f) = t.transpose();
        m.face_node.conservativeResize(f + 1);
        m.face_material.conservativeResize(f + 1);
        m.face_back_material.conservativeResize(f + 1);
        m.face_node[f] = node;
        m.face_material[f] = material;
        m.face_back_material[f] = back_material;
      }
    }
}

//! Empty model with materials and nodes (one material per node, node i uses material i).
inline ThermalModel model_with(const std::vector<std::string>& nodes, const std::vector<Material>& materials) {
  ThermalModel model;
  model.mesh.V.resize(0, 3);
  model.mesh.F.resize(0, 3);
  model.materials = materials;
  for (const auto& m : materials) model.mesh.material_names.push_back(m.name);
  for (size_t i = 0; i < nodes.size(); ++i) {
    Node n;
    n.name = nodes[i];
    n.material = static_cast<int>(std::min(i, materials.size() - 1));
    n.capacitance_J_per_K = 1000.0;
    model.nodes.push_back(n);
    model.mesh.node_names.push_back(nodes[i]);
  }
  model.analysis.type = AnalysisType::steady;
  model.radiation.rays_per_face = 2000;
  return model;
}

//! Axis-aligned cube [-h, h]^3 with outward faces; face k (+X, -X, +Y, -Y, +Z, -Z) goes to
//! node node_of_face[k] (default all node 0) with material 0. One-sided (closed solid).
inline void add_cube(Mesh& m, double h, const std::vector<int>& node_of_face = {0, 0, 0, 0, 0, 0}, int n = 2) {
  const double s = 2 * h;
  using V = Eigen::Vector3d;
  add_quad(m, V(h, -h, -h), V(0, s, 0), V(0, 0, s), node_of_face[0], 0, -1, n);   // +X
  add_quad(m, V(-h, -h, -h), V(0, 0, s), V(0, s, 0), node_of_face[1], 0, -1, n);  // -X
  add_quad(m, V(-h, h, -h), V(0, 0, s), V(s, 0, 0), node_of_face[2], 0, -1, n);   // +Y
  add_quad(m, V(-h, -h, -h), V(s, 0, 0), V(0, 0, s), node_of_face[3], 0, -1, n);  // -Y
  add_quad(m, V(-h, -h, h), V(s, 0, 0), V(0, s, 0), node_of_face[4], 0, -1, n);   // +Z
  add_quad(m, V(-h, -h, -h), V(0, s, 0), V(s, 0, 0), node_of_face[5], 0, -1, n);  // -Z
}

}  // namespace thermodec::testing
