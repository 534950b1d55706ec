// DecimationOptions::near_contact_fraction: a vertex within that fraction of its shortest edge
// of another node's face (a non-conforming contact, a gap far below the edge lengths) stays
// where it is; nodes apart from each other decimate exactly as without the option.
#include <gtest/gtest.h>

#include <limits>

#include "decimation/test_meshes.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/decimate_nodes.h"

using namespace thermodec;
using thermodec::test::MeshBuilder;

namespace {

// Node 0: an 8 x 8 plate [0,1]^2 at z = 0. Node 1: an 8 x 8 plate [0.3, 0.7]^2 `gap` [m]
// above it (its edges 0.05 m, none of its vertices on node 0's).
Mesh plate_over_plate(double gap) {
  MeshBuilder b;
  b.grid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), 8, 0);
  b.grid(Eigen::Vector3d(0.3, 0.3, gap), Eigen::Vector3d(0.4, 0, 0), Eigen::Vector3d(0, 0.4, 0), 8, 1);
  return b.build(2);
}

}  // namespace

TEST(NearContacts, a_plate_resting_a_tenth_of_a_millimetre_above_another_keeps_its_vertices) {
  // 0.1 mm: 0.2 % of the upper plate's 0.05 m edges and 7e-5 of the model's 1.4 m diagonal.
  const Mesh in = plate_over_plate(1e-4);
  DecimationOptions o;
  const Eigen::Vector2d ratios(0.9, 0.9);
  const DecimationResult free_run = decimate_nodes(in, ratios, o);
  EXPECT_LT(free_run.nodes[1].faces_after, free_run.nodes[1].faces_before / 2);
  o.near_contact_fraction = 0.05;
  const DecimationResult r = decimate_nodes(in, ratios, o);
  // Every vertex of the upper plate lies 0.1 mm over the lower one: all frozen, nothing moves.
  EXPECT_EQ(r.nodes[1].faces_after, r.nodes[1].faces_before);
  for (int f = 0; f < r.mesh.num_faces(); ++f)
    for (int j = 0; j < 3; ++j) {
      const int v = r.mesh.F(f, j);
      if (r.mesh.face_node[f] == 1) EXPECT_EQ((r.mesh.V.row(v) - in.V.row(r.fine_vertex_of_coarse[v])).norm(), 0.0);
    }
  // The lower plate keeps the vertices under the upper one and still decimates around them.
  EXPECT_LT(r.nodes[0].faces_after, r.nodes[0].faces_before);
  EXPECT_GT(r.nodes[0].faces_after, free_run.nodes[0].faces_after);
}

TEST(NearContacts, plates_apart_decimate_as_without_the_option) {
  // 2 mm: within 5 % of the upper plate's edges, but 1.4e-3 of the model's size, a gap and
  // not a contact; 0.2 m: 4 of its edges.
  for (const double gap : {0.002, 0.2}) {
    const Mesh in = plate_over_plate(gap);
    DecimationOptions o;
    const Eigen::Vector2d ratios(0.9, 0.9);
    const DecimationResult a = decimate_nodes(in, ratios, o);
    o.near_contact_fraction = 0.05;
    const DecimationResult b = decimate_nodes(in, ratios, o);
    ASSERT_EQ(a.mesh.num_faces(), b.mesh.num_faces());
    EXPECT_EQ(a.mesh.F, b.mesh.F);
    EXPECT_EQ(a.mesh.V, b.mesh.V);
  }
}

TEST(NearContacts, a_sheet_standing_on_a_plate_without_shared_vertices_is_not_a_contact) {
  // The upper plate turned upright: its foot edge rests 0.1 mm over the lower plate, its faces
  // perpendicular to it. Only nearly parallel faces overlap at a contact: nothing is frozen.
  MeshBuilder m;
  m.grid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), 8, 0);
  m.grid(Eigen::Vector3d(0.3, 0.51, 1e-4), Eigen::Vector3d(0.4, 0, 0), Eigen::Vector3d(0, 0, 0.4), 8, 1);
  const Mesh in = m.build(2);
  DecimationOptions o;
  const Eigen::Vector2d ratios(0.9, 0.9);
  const DecimationResult a = decimate_nodes(in, ratios, o);
  o.near_contact_fraction = 0.05;
  const DecimationResult b = decimate_nodes(in, ratios, o);
  EXPECT_EQ(a.mesh.F, b.mesh.F);
  EXPECT_EQ(a.mesh.V, b.mesh.V);
}

TEST(NearContacts, a_negative_or_infinite_fraction_is_refused) {
  const Mesh in = plate_over_plate(0.002);
  DecimationOptions o;
  o.near_contact_fraction = -0.1;
  EXPECT_THROW(decimate_nodes(in, Eigen::Vector2d(0.5, 0.5), o), InvalidInput);
  o.near_contact_fraction = std::numeric_limits<double>::infinity();
  EXPECT_THROW(decimate_nodes(in, Eigen::Vector2d(0.5, 0.5), o), InvalidInput);
}
