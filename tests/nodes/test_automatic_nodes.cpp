#include <gtest/gtest.h>

#include <set>

#include "thermodec/common/errors.h"
#include "thermodec/nodes/automatic_nodes.h"

using namespace thermodec;

namespace {

// Axis-aligned box [0,sx]x[0,sy]x[0,sz], every side an n x n grid of triangle pairs with
// shared (welded) vertices, normals pointing outwards.
Mesh grid_box(int n, double sx = 1.0, double sy = 1.0, double sz = 1.2) {
  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> faces;
  auto vertex = [&](const Eigen::Vector3d& p) {
    for (int i = 0; i < static_cast<int>(verts.size()); ++i)
      if ((verts[i] - p).norm() < 1e-12) return i;
    verts.push_back(p);
    return static_cast<int>(verts.size()) - 1;
  };
  const Eigen::Vector3d size(sx, sy, sz);
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          auto at = [&](int a, int b) {
            Eigen::Vector3d p;
            p[axis] = side * size[axis];
            p[u] = size[u] * a / n;
            p[v] = size[v] * b / n;
            return vertex(p);
          };
          const int p00 = at(i, j), p10 = at(i + 1, j), p11 = at(i + 1, j + 1), p01 = at(i, j + 1);
          // (u, v, axis) is right-handed, so u x v = +axis: flip on the low side.
          if (side == 1) {
            faces.emplace_back(p00, p10, p11);
            faces.emplace_back(p00, p11, p01);
          } else {
            faces.emplace_back(p00, p11, p10);
            faces.emplace_back(p00, p01, p11);
          }
        }
      }
    }
  }
  Mesh mesh;
  mesh.V.resize(verts.size(), 3);
  for (int i = 0; i < static_cast<int>(verts.size()); ++i) mesh.V.row(i) = verts[i].transpose();
  mesh.F.resize(faces.size(), 3);
  for (int i = 0; i < static_cast<int>(faces.size()); ++i) mesh.F.row(i) = faces[i].transpose();
  mesh.face_node = Eigen::VectorXi::Constant(mesh.num_faces(), -1);
  mesh.face_material = Eigen::VectorXi::Constant(mesh.num_faces(), -1);
  mesh.face_back_material = Eigen::VectorXi::Constant(mesh.num_faces(), -1);
  return mesh;
}

}  // namespace

TEST(AutomaticNodes, box_splits_into_its_six_sides) {
  Mesh mesh = grid_box(4);
  assign_automatic_nodes(mesh);
  ASSERT_EQ(mesh.node_names.size(), 6u);
  EXPECT_EQ(mesh.node_names.front(), "node_000");
  EXPECT_EQ(mesh.node_names.back(), "node_005");
  // Every side (32 consecutive faces) is exactly one node.
  std::set<int> seen;
  for (int side = 0; side < 6; ++side) {
    const int node = mesh.face_node[side * 32];
    for (int f = side * 32; f < (side + 1) * 32; ++f) ASSERT_EQ(mesh.face_node[f], node) << "face " << f;
    seen.insert(node);
  }
  EXPECT_EQ(seen.size(), 6u);
}
