// DecimationOptions::release_contacts: a flat region a part only touches (a fin standing on a
// plate, a pyramid's apex resting on it) keeps no vertex of the contact, the touching part
// keeps its own exactly, and copies left unmoved are joined back.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "decimation/test_meshes.h"
#include "thermodec/decimation/decimate_nodes.h"

using namespace thermodec;
using thermodec::test::MeshBuilder;
using thermodec::test::edge_counts;

namespace {

// A 4 x 4 plate [0,1]^2 (node 0) with a 2 x 2 fin (node 1) standing on the segment
// x in [0.25, 0.75], y = 0.5 (three plate vertices inside the plate), and a square pyramid
// (node 2) whose apex rests on the plate vertex (0.25, 0.25, 0) from below.
Mesh plate_with_contacts() {
  MeshBuilder b;
  b.grid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), 4, 0);
  b.grid(Eigen::Vector3d(0.25, 0.5, 0), Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0, 0, 0.5), 2, 1);
  const int apex = b.vertex({0.25, 0.25, 0});
  int base[4];
  const double xy[4][2] = {{0.15, 0.15}, {0.35, 0.15}, {0.35, 0.35}, {0.15, 0.35}};
  for (int k = 0; k < 4; ++k) base[k] = b.vertex({xy[k][0], xy[k][1], -0.2});
  for (int k = 0; k < 4; ++k) b.face(apex, base[(k + 1) % 4], base[k], 2);
  b.face(base[0], base[1], base[2], 2);
  b.face(base[0], base[2], base[3], 2);
  return b.build(3);
}

}  // namespace

TEST(ContactRelease, a_plate_holding_a_fin_and_an_apex_goes_to_its_two_outline_triangles) {
  const Mesh in = plate_with_contacts();
  DecimationOptions o;
  const Eigen::Vector3d ratios(0.999, 0, 0);
  // Conforming: the plate keeps the fin's three foot vertices and the apex inside it
  // (4 corners and 4 interior points: 4 + 2 * 4 - 2 = 10 triangles).
  const DecimationResult kept = decimate_nodes(in, ratios, o);
  EXPECT_EQ(kept.nodes[0].faces_after, 10);
  o.release_contacts = true;
  const DecimationResult r = decimate_nodes(in, ratios, o);
  EXPECT_EQ(r.nodes[0].faces_after, 2);
  EXPECT_NEAR(r.nodes[0].area_after_m2, 1.0, 1e-12);
  for (int n : {1, 2}) EXPECT_EQ(r.nodes[n].faces_after, r.nodes[n].faces_before);
  // The touching parts are untouched: every vertex of theirs keeps its input coordinates, and
  // the plate's faces all stay in its plane.
  for (int f = 0; f < r.mesh.num_faces(); ++f)
    for (int j = 0; j < 3; ++j) {
      const int v = r.mesh.F(f, j);
      if (r.mesh.face_node[f] != 0)
        EXPECT_EQ((r.mesh.V.row(v) - in.V.row(r.fine_vertex_of_coarse[v])).norm(), 0.0);
      else
        EXPECT_EQ(r.mesh.V(v, 2), 0.0);
    }
  // Provenance: every output vertex names an input vertex at its place.
  ASSERT_EQ(r.fine_vertex_of_coarse.size(), r.mesh.num_vertices());
  for (int v = 0; v < r.mesh.num_vertices(); ++v) {
    ASSERT_GE(r.fine_vertex_of_coarse[v], 0);
    ASSERT_LT(r.fine_vertex_of_coarse[v], in.num_vertices());
  }
}

TEST(ContactRelease, copies_left_unmoved_are_joined_back_so_an_untouched_contact_stays_conforming) {
  const Mesh in = plate_with_contacts();
  DecimationOptions o;
  o.release_contacts = true;
  const DecimationResult r = decimate_nodes(in, Eigen::Vector3d(0, 0.5, 0), o);
  EXPECT_LT(r.nodes[1].faces_after, r.nodes[1].faces_before);
  EXPECT_EQ(r.nodes[0].faces_after, r.nodes[0].faces_before);
  // The fin's foot (two edges of three faces) is still shared with the plate, and no vertex
  // is duplicated.
  int nm_in = 0, nm_out = 0;
  for (const auto& [e, n] : edge_counts(in)) nm_in += n > 2;
  for (const auto& [e, n] : edge_counts(r.mesh)) nm_out += n > 2;
  EXPECT_EQ(nm_in, 2);
  EXPECT_EQ(nm_out, nm_in);
  std::set<int> inputs(r.fine_vertex_of_coarse.data(), r.fine_vertex_of_coarse.data() + r.fine_vertex_of_coarse.size());
  EXPECT_EQ(inputs.size(), static_cast<size_t>(r.mesh.num_vertices()));
}

TEST(ContactRelease, a_fin_across_a_whole_plate_and_a_bow_tie_decimate_node_preserving_and_repeatably) {
  // The fin's foot runs from edge to edge of the plate: its two end vertices lie on the plate's
  // outline (their fans are not closed) and stay shared; the inner ones are released.
  const Mesh in = test::non_manifold_fin(8);
  DecimationOptions o;
  o.release_contacts = true;
  const Eigen::Vector3d ratios(0.9, 0.7, 0.5);
  const DecimationResult r = decimate_nodes(in, ratios, o);
  ASSERT_EQ(r.fine_face_of_coarse.size(), r.mesh.num_faces());
  for (int i = 0; i < r.mesh.num_faces(); ++i) {
    EXPECT_EQ(r.mesh.face_node[i], in.face_node[r.fine_face_of_coarse[i]]);
    EXPECT_NE(r.mesh.F(i, 0), r.mesh.F(i, 1));
    EXPECT_NE(r.mesh.F(i, 1), r.mesh.F(i, 2));
    EXPECT_NE(r.mesh.F(i, 0), r.mesh.F(i, 2));
  }
  for (const auto& s : r.nodes) EXPECT_LE(std::abs(s.relative_area_change()), o.max_relative_area_change + 1e-12);
  // No crack: both ends of every open edge of the output are input vertices that were on the
  // input's open boundary or on an edge of > 2 faces (the fin's foot, now resting on the plate).
  std::set<int> rim;
  for (const auto& [e, n] : edge_counts(in))
    if (n != 2) rim.insert({e.first, e.second});
  for (const auto& [e, n] : edge_counts(r.mesh))
    if (n == 1) {
      const int a = r.fine_vertex_of_coarse[e.first], b = r.fine_vertex_of_coarse[e.second];
      EXPECT_TRUE(rim.count(a) && rim.count(b)) << "new open edge " << a << "-" << b;
    }
  const DecimationResult again = decimate_nodes(in, ratios, o);
  EXPECT_TRUE(again.mesh.V == r.mesh.V && again.mesh.F == r.mesh.F);
  EXPECT_LT(r.nodes[0].faces_after, decimate_nodes(in, ratios, DecimationOptions{}).nodes[0].faces_after);
}
