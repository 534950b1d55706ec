#include <gtest/gtest.h>

#include <random>

#include "mesh/mesh_test_util.h"
#include "thermodec/mesh/face_geometry.h"
#include "thermodec/mesh/mesh_stats.h"
#include "thermodec/mesh/weld.h"
#include "thermodec/common/errors.h"

using namespace thermodec;
using thermodec::test::unit_cube;

TEST(FaceGeometry, cube_faces_have_half_unit_area_and_outward_normals) {
  const Mesh cube = unit_cube();
  const Eigen::VectorXd A = face_areas(cube.V, cube.F);
  for (int f = 0; f < 12; ++f) EXPECT_DOUBLE_EQ(A[f], 0.5);
  const Eigen::MatrixXd N = face_normals(cube.V, cube.F);
  EXPECT_EQ(N.row(0), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(N.row(3), Eigen::RowVector3d(-1, 0, 0));
  EXPECT_EQ(N.row(8), Eigen::RowVector3d(0, 0, 1));
}

TEST(FaceGeometry, degenerate_test_is_scale_independent) {
  Eigen::MatrixXd V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1e-3, 0;
  Eigen::MatrixXi F(3, 3);
  F << 0, 1, 2,  // collinear
      0, 1, 3,   // thin but real
      0, 0, 3;   // repeated corner
  EXPECT_EQ(degenerate_faces(V, F), (std::vector<int>{0, 2}));
  EXPECT_EQ(degenerate_faces(V * 1e-6, F), (std::vector<int>{0, 2}));
  EXPECT_EQ(degenerate_faces(V * 1e6, F), (std::vector<int>{0, 2}));
  EXPECT_EQ(face_normals(V, F).row(0), Eigen::RowVector3d::Zero());
}

TEST(Weld, merges_within_tolerance_into_first_vertex_deterministically) {
  Eigen::MatrixXd V(5, 3);
  V << 0, 0, 0,  //
      1, 0, 0,   //
      0.5e-3, 0, 0,  // near vertex 0
      1, 0.9e-3, 0,  // near vertex 1
      1, 1.8e-3, 0;  // near vertex 3 but not 1: not merged transitively
  const WeldResult w = weld_vertices(V, 1e-3);
  EXPECT_EQ(w.new_index, (Eigen::VectorXi(5) << 0, 1, 0, 1, 2).finished());
  ASSERT_EQ(w.V.rows(), 3);
  EXPECT_EQ(w.V.row(0), V.row(0));
  EXPECT_EQ(w.V.row(2), V.row(4));
  EXPECT_EQ(weld_vertices(V, 0).V.rows(), 5);
}

TEST(Weld, rejects_negative_or_nan_tolerance) {
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(2, 3);
  EXPECT_THROW(weld_vertices(V, -1), InvalidInput);
  EXPECT_THROW(weld_vertices(V, std::nan("")), InvalidInput);
}

TEST(Weld, finds_neighbours_across_grid_cells) {
  // Points straddling a cell boundary at x = 0 must still merge.
  Eigen::MatrixXd V(2, 3);
  V << -1e-10, 5, 5, 1e-10, 5, 5;
  EXPECT_EQ(weld_vertices(V, 1e-9).V.rows(), 1);
}

TEST(MeshStats, closed_cube_has_no_boundary_and_one_component) {
  const MeshStats s = mesh_stats(unit_cube());
  EXPECT_EQ(s.faces, 12);
  EXPECT_EQ(s.vertices, 8);
  EXPECT_EQ(s.edges, 18);
  EXPECT_EQ(s.components, 1);
  EXPECT_EQ(s.boundary_edges, 0);
  EXPECT_EQ(s.non_manifold_edges, 0);
  EXPECT_EQ(s.degenerate_faces, 0);
  EXPECT_DOUBLE_EQ(s.area_m2, 6.0);
}

TEST(MeshStats, open_fin_on_cube_edge_is_non_manifold_and_separate_sheet_counts) {
  Mesh m = unit_cube();
  // A fin triangle hanging off the cube edge (1,3): that edge now has three faces.
  m.V.conservativeResize(12, 3);
  m.V.row(8) << 2, 0.5, 0;
  // A separate triangle far away: its own component with three boundary edges.
  m.V.row(9) << 5, 5, 5;
  m.V.row(10) << 6, 5, 5;
  m.V.row(11) << 5, 6, 5;
  m.F.conservativeResize(14, 3);
  m.F.row(12) << 1, 3, 8;
  m.F.row(13) << 9, 10, 11;
  const MeshStats s = mesh_stats(m);
  EXPECT_EQ(s.non_manifold_edges, 1);
  EXPECT_EQ(s.boundary_edges, 2 + 3);
  EXPECT_EQ(s.components, 2);
}

TEST(MeshStats, per_node_counts_areas_and_materials) {
  const Mesh cube = unit_cube();
  const auto counts = node_face_counts(cube);
  const auto areas = node_areas_m2(cube);
  const auto mats = node_materials(cube);
  ASSERT_EQ(counts.size(), 6u);
  for (int n = 0; n < 6; ++n) {
    EXPECT_EQ(counts[n], 2);
    EXPECT_DOUBLE_EQ(areas[n], 1.0);
  }
  EXPECT_EQ(mats[0], std::vector<int>{1});
  EXPECT_EQ(mats[1], std::vector<int>{0});
}

TEST(MeshStats, components_touching_at_a_vertex_are_separate) {
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 2, 3, 4;
  const Eigen::VectorXi c = face_components(F);
  EXPECT_EQ(c, Eigen::Vector2i(0, 1));
}

TEST(Weld, hash_grid_matches_brute_force_greedy_clustering) {
  // Points scattered around a few centres at distances of the order of the tolerance, so
  // many pairs straddle cell faces and the tolerance itself.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> centre(-1.0, 1.0), jitter(-1.5e-3, 1.5e-3);
  const double tol = 1e-3;
  Eigen::MatrixXd V(600, 3);
  Eigen::MatrixXd C(40, 3);
  for (int i = 0; i < 40; ++i) C.row(i) << centre(rng), centre(rng), centre(rng);
  for (int i = 0; i < 600; ++i) V.row(i) = C.row(i % 40) + Eigen::RowVector3d(jitter(rng), jitter(rng), jitter(rng));
  std::vector<int> kept, expected(600);
  for (int i = 0; i < 600; ++i) {
    int found = -1;
    for (int j = 0; j < static_cast<int>(kept.size()) && found < 0; ++j)
      if ((V.row(kept[j]) - V.row(i)).squaredNorm() <= tol * tol) found = j;
    if (found < 0) {
      found = static_cast<int>(kept.size());
      kept.push_back(i);
    }
    expected[i] = found;
  }
  const WeldResult w = weld_vertices(V, tol);
  ASSERT_EQ(w.V.rows(), static_cast<Eigen::Index>(kept.size()));
  for (int i = 0; i < 600; ++i) EXPECT_EQ(w.new_index[i], expected[i]) << i;
}
