#include <gtest/gtest.h>

#include "test_meshes.h"
#include "thermodec/common/errors.h"
#include "thermodec/radiation/external_geometry.h"

using namespace thermodec;
using namespace thermodec::test;

namespace {
// Outer box (node 0) around an inner box (node 1) and an internal partition (node 2, two-sided).
// With `open_top`, the outer box has no +z wall.
Mesh nested_boxes(bool open_top) {
  Mesh mesh;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  box({-1, -1, -1}, {1, 1, 1}, false, 4, V, F);
  if (open_top) {  // box() emits 6 walls of 32 faces: z-, z+, ...; drop z+
    Eigen::MatrixXi G(F.rows() - 32, 3);
    G << F.topRows(32), F.bottomRows(F.rows() - 64);
    F = G;
  }
  append_part(mesh, V, F, "outer");
  box({-0.3, -0.3, -0.3}, {0.3, 0.3, 0.3}, false, 2, V, F);
  append_part(mesh, V, F, "inner");
  grid({-0.9, 0.6, -0.9}, {1.8, 0, 0}, {0, 0, 1.8}, 3, 3, V, F);
  append_part(mesh, V, F, "partition", 0);
  return mesh;
}
}  // namespace

TEST(ExternalGeometry, drops_a_box_inside_a_closed_box_and_internal_walls) {
  const Mesh mesh = nested_boxes(false);
  const ExternalFaces ext = external_faces(RayScene(mesh));
  EXPECT_EQ(ext.kept_per_node[0], 6 * 32);
  EXPECT_EQ(ext.dropped_per_node[0], 0);
  EXPECT_EQ(ext.kept_per_node[1], 0);
  EXPECT_EQ(ext.dropped_per_node[1], 6 * 8);
  EXPECT_EQ(ext.kept_per_node[2], 0);
  Eigen::VectorXi original;
  const Mesh out = extract_external(mesh, ext, &original);
  EXPECT_EQ(out.num_faces(), 6 * 32);
  for (int i = 0; i < out.num_faces(); ++i) {
    EXPECT_EQ(out.face_node[i], 0);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(out.V.row(out.F(i, k)), mesh.V.row(mesh.F(original[i], k)));
  }
}

TEST(ExternalGeometry, keeps_what_is_seen_through_an_opening) {
  const Mesh mesh = nested_boxes(true);
  const ExternalFaces ext = external_faces(RayScene(mesh));
  // Through the open top one sees: the inner box's top and its 4 walls, the partition (both
  // sides) and the inside of... nothing else: the outer walls are one-sided, facing out.
  EXPECT_EQ(ext.kept_per_node[0], 5 * 32);
  EXPECT_EQ(ext.kept_per_node[1], 5 * 8) << "all but the inner box's bottom";
  EXPECT_EQ(ext.dropped_per_node[1], 8);
  EXPECT_EQ(ext.kept_per_node[2], 18);
}

TEST(ExternalGeometry, is_deterministic_and_checks_its_settings) {
  const Mesh mesh = nested_boxes(true);
  const RayScene scene(mesh);
  EXPECT_EQ(external_faces(scene).external, external_faces(scene).external);
  EXPECT_THROW(external_faces(scene, ExternalSettings{0}), InvalidInput);
}
