#include <gtest/gtest.h>

#include <map>
#include <set>

#include "decimation/test_meshes.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/mesh/repair.h"

using namespace thermodec;
using thermodec::test::MeshBuilder;
using thermodec::test::edge_counts;

namespace {
double area(const Mesh& m) {
  double s = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    s += 0.5 * (b - a).cross(c - a).norm();
  }
  return s;
}
double volume(const Mesh& m) {
  double s = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    s += a.dot(b.cross(c)) / 6;
  }
  return s;
}
}  // namespace

TEST(Repair, clean_box_is_left_unchanged) {
  const Mesh box = test::subdivided_box(3, true);
  const RepairResult r = repair_mesh(box);
  EXPECT_FALSE(r.report.changed()) << r.report.summary();
  EXPECT_EQ(r.mesh.F, box.F);
  EXPECT_EQ(r.report.open_edges, 0);
}

TEST(Repair, welds_split_vertices_and_drops_degenerate_and_duplicate_faces) {
  MeshBuilder b;
  const int a = b.raw_vertex({0, 0, 0}), c = b.raw_vertex({1, 0, 0}), d = b.raw_vertex({0, 1, 0});
  const int c2 = b.raw_vertex({1, 0, 1e-12}), d2 = b.raw_vertex({0, 1, 0}), e = b.raw_vertex({1, 1, 0});
  b.face(a, c, d, 0);
  b.face(c2, e, d2, 0);
  b.face(d, c, e, 0);          // duplicate of the second face once welded (other winding)
  b.face(a, a, c, 0);          // repeated corner
  b.face(a, c, b.raw_vertex({0.5, 0, 0}), 0);  // zero area (cap)
  const Mesh m = b.build(1);
  const RepairResult r = repair_mesh(m);
  EXPECT_EQ(r.report.vertices_welded, 2);
  EXPECT_EQ(r.report.degenerate_faces_dropped, 2);
  EXPECT_EQ(r.report.duplicate_faces_dropped, 1);
  EXPECT_EQ(r.mesh.num_faces(), 2);
  EXPECT_EQ(r.mesh.num_vertices(), 4);
  EXPECT_EQ(r.report.open_edges, 4);
  EXPECT_NEAR(area(r.mesh), 1.0, 1e-9);
}

TEST(Repair, t_junction_is_split_by_edge_bisection_and_becomes_conforming) {
  const Mesh t = test::t_junction_mesh();  // 2 coarse + 8 fine faces, 2 + 9 vertices
  const RepairResult r = repair_mesh(t);
  EXPECT_EQ(r.report.vertices_welded, 2);   // the two shared corners
  EXPECT_EQ(r.report.t_junctions_split, 1); // (1, 0.5) bisects the coarse face on x = 1
  EXPECT_EQ(r.mesh.num_faces(), 11);
  EXPECT_NEAR(area(r.mesh), 2.0, 1e-12);
  // Conforming: the only open edges are on the 2 x 1 rectangle's perimeter (6 + 2 segments... )
  for (const auto& [e, n] : edge_counts(r.mesh)) {
    ASSERT_LE(n, 2);
    if (n == 1) {
      const Eigen::Vector3d p = r.mesh.V.row(e.first), q = r.mesh.V.row(e.second);
      const bool on_perimeter = (p.x() == q.x() && (p.x() == 0 || p.x() == 2)) ||
                                (p.y() == q.y() && (p.y() == 0 || p.y() == 1));
      EXPECT_TRUE(on_perimeter) << p.transpose() << " - " << q.transpose();
    }
  }
  // Split faces keep their node: the coarse square's faces are node 0.
  for (int f = 0; f < r.mesh.num_faces(); ++f) EXPECT_EQ(r.mesh.face_node[f], t.face_node[r.source_face[f]]);
  // And the repaired mesh decimates with its interface intact.
  const DecimationResult d = decimate_nodes(r.mesh, Eigen::Vector2d(0.5, 0.5));
  for (const auto& [e, n] : edge_counts(d.mesh)) EXPECT_LE(n, 2);
}

TEST(Repair, inconsistent_orientation_is_made_outward) {
  Mesh box = test::subdivided_box(3, true);
  int flipped_in = 0;
  for (int f = 0; f < box.num_faces(); f += 5) {
    std::swap(box.F(f, 1), box.F(f, 2));
    ++flipped_in;
  }
  const RepairResult r = repair_mesh(box);
  EXPECT_EQ(r.report.faces_flipped, flipped_in);
  EXPECT_EQ(r.report.orientation_conflicts, 0);
  EXPECT_NEAR(volume(r.mesh), 1.0, 1e-12);
  // Fully inverted closed box: every face turns.
  Mesh inverted = test::subdivided_box(2, false);
  for (int f = 0; f < inverted.num_faces(); ++f) std::swap(inverted.F(f, 1), inverted.F(f, 2));
  const RepairResult ri = repair_mesh(inverted);
  EXPECT_EQ(ri.report.faces_flipped, inverted.num_faces());
  EXPECT_NEAR(volume(ri.mesh), 1.0, 1e-12);
}

TEST(Repair, two_sided_faces_swap_materials_when_flipped) {
  MeshBuilder b;
  b.grid({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 0, 0, 1);
  Mesh m = b.build(1);
  std::swap(m.F(1, 1), m.F(1, 2));
  const RepairResult r = repair_mesh(m);
  ASSERT_EQ(r.report.faces_flipped, 1);
  EXPECT_EQ(r.mesh.face_material[1], 1);
  EXPECT_EQ(r.mesh.face_back_material[1], 0);
}

TEST(Repair, non_manifold_fin_is_carried_and_reported) {
  const Mesh fin = test::non_manifold_fin(4);
  const RepairResult r = repair_mesh(fin);
  EXPECT_EQ(r.report.non_manifold_edges, 4);
  EXPECT_GE(r.report.non_manifold_vertices, 1);  // the bow-tie corner
  EXPECT_EQ(r.mesh.num_faces(), fin.num_faces());
  EXPECT_NE(r.report.summary().find("non-manifold edges (kept): 4"), std::string::npos);
}

TEST(Repair, invalid_input_is_rejected) {
  Mesh m = test::two_node_plate(1);
  m.V(0, 0) = std::nan("");
  EXPECT_THROW(repair_mesh(m), InvalidInput);
  RepairOptions o;
  o.relative_tolerance = -1;
  EXPECT_THROW(repair_mesh(test::two_node_plate(1), o), InvalidInput);
}
