// The area-weighted normal check (DecimationOptions::projected_area_budget): a sliver may turn
// past max_normal_deviation_deg when its node pays the change of its area vector, a fold is
// refused whatever the budget.
#include <gtest/gtest.h>

#include <vector>

#include "decimation/test_meshes.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/decimate_nodes.h"

namespace thermodec {
namespace {

using Eigen::Vector3d;

// One node: a fan around g = (0,0,0) on the straight open rim from w = (-1,0,0) to k = (1,0,0),
// its other corners `ring` (from k round to w) below the rim. g can only go into k or into w
// (every other edge joins two rim vertices across the fan, or is a rim kink beyond
// max_contour_deviation).
Mesh rim_fan(const std::vector<Vector3d>& ring) {
  test::MeshBuilder b;
  const int g = b.vertex(Vector3d(0, 0, 0));
  std::vector<int> r;
  for (const auto& p : ring) r.push_back(b.vertex(p));
  for (size_t i = 0; i + 1 < r.size(); ++i) b.face(g, r[i + 1], r[i], 0);
  return b.build(1);
}

// Asks for one face less than the fan has.
Eigen::VectorXd one_face_less(const Mesh& m) { return Eigen::VectorXd::Constant(1, 1.0 / m.num_faces()); }

// Whichever way g goes, the 0.01 m^2 vertical sliver (g, r6, r7) (r7 5 cm under r6) turns by
// 68 degrees: the per-face check refuses both collapses. Its area vector changes by 0.025 m^2,
// 6 % of the node's 0.41 m^2, within a budget of 1 x the 10 % area bound: the area-weighted
// check lets it go, and the flat faces keep their orientation.
TEST(ProjectedAreaBudget, a_sliver_turning_68_degrees_goes_when_its_node_pays_for_it) {
  const Mesh fan = rim_fan({{1, 0, 0}, {0, -0.4, 0}, {0, -0.4, -0.05}, {-1, 0, 0}});
  DecimationOptions per_face;
  per_face.max_relative_area_change = 0.1;  // the sliver's growth (+4.5 % of the node) is not what is tested
  const DecimationResult before = decimate_nodes(fan, one_face_less(fan), per_face);
  EXPECT_EQ(before.mesh.num_faces(), 3);
  EXPECT_EQ(before.nodes[0].blocked_edges[static_cast<int>(CollapseBlock::normal_deviation)], 2);  // g-k, g-w

  DecimationOptions weighted = per_face;
  weighted.projected_area_budget = 1.0;
  weighted.max_kinked_contour_deviation = weighted.max_contour_deviation;  // steep turns alone
  const DecimationResult after = decimate_nodes(fan, one_face_less(fan), weighted);
  EXPECT_EQ(after.mesh.num_faces(), 2);
  EXPECT_TRUE(after.nodes[0].reached);

  // A budget too small for the sliver's 0.025 m^2 refuses it, and says so.
  weighted.projected_area_budget = 0.5;  // 0.5 x 10 % x 0.41 m^2 = 0.021 m^2
  const DecimationResult poor = decimate_nodes(fan, one_face_less(fan), weighted);
  EXPECT_EQ(poor.mesh.num_faces(), 3);
  EXPECT_EQ(poor.nodes[0].blocked_edges[static_cast<int>(CollapseBlock::projected_area_budget)], 2);
}

// A flat fan whose middle corner sits just under the rim: g into k flips the face (g, p2, p3),
// g into w the face (g, p1, p2), each 11 % of the node's area, by 180 degrees. Both checks
// refuse, whatever the budget: no fold-overs.
TEST(ProjectedAreaBudget, a_large_face_flip_is_refused_by_both_checks) {
  const Mesh fan = rim_fan({{1, 0, 0}, {0.9, -0.16, 0}, {0, -0.05, 0}, {-0.9, -0.16, 0}, {-1, 0, 0}});
  DecimationOptions per_face;
  per_face.max_relative_area_change = 1.0;  // only the normal checks can refuse
  DecimationOptions weighted = per_face;
  weighted.projected_area_budget = 1e3;
  weighted.max_kinked_contour_deviation = weighted.max_contour_deviation;
  for (const auto& o : {per_face, weighted}) {
    const DecimationResult r = decimate_nodes(fan, one_face_less(fan), o);
    EXPECT_EQ(r.mesh.num_faces(), 4);
    EXPECT_EQ(r.nodes[0].blocked_edges[static_cast<int>(CollapseBlock::normal_deviation)], 2);  // g-k, g-w
  }
}

// A flat 1 m x 1 m panel (4 x 4 grid) whose rim has one kink: the vertex at (0.5, 0) moved out
// to (0.5, -0.05), 0.1 of the 0.5 m segment that replaces it and 0.05 of the whole side. The
// per-vertex check keeps it whatever the ratio; with a budget the panel pays the 0.0125-0.025 m^2
// its outline sweeps and the kink goes.
TEST(ProjectedAreaBudget, a_small_rim_kink_goes_when_its_node_pays_for_the_swept_outline) {
  test::MeshBuilder b;
  b.grid(Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0), 4, 0);
  b.v[b.vertex(Vector3d(0.5, 0, 0))] = Vector3d(0.5, -0.05, 0);
  const Mesh panel = b.build(1);
  auto kink_kept = [](const Mesh& m) {
    for (int v = 0; v < m.num_vertices(); ++v)
      if (m.V(v, 1) < -0.04) return true;
    return false;
  };
  DecimationOptions per_vertex;
  per_vertex.max_relative_area_change = 0.05;  // the kink's 1-2.5 % of area is not what is tested
  const DecimationResult before = decimate_nodes(panel, Eigen::VectorXd::Constant(1, 0.95), per_vertex);
  EXPECT_TRUE(kink_kept(before.mesh));
  DecimationOptions weighted = per_vertex;
  weighted.projected_area_budget = 1.0;  // 0.05 x 1.025 m^2
  const DecimationResult after = decimate_nodes(panel, Eigen::VectorXd::Constant(1, 0.95), weighted);
  EXPECT_FALSE(kink_kept(after.mesh));
  EXPECT_LT(after.mesh.num_faces(), before.mesh.num_faces());
}

// The same 1 m panel with its rim vertex at (0.5, -0.4): the rim vertices beside it go as kinks
// within the relative cap (0.16 of their segments), the vertex itself would then be 0.4 of the
// 1 m segment from (0, 0) to (1, 0), past the cap of 0.2, and its outline would sweep 0.2 m^2.
// Under the projected-area cap with wide_kink_area_fraction 0.1 it goes where that is at most a
// tenth of what the node's area may move: not on the panel alone (0.1 x 0.2 x 1.2 m^2 =
// 0.024 m^2), but when the same node also holds a 10 m x 10 m plate elsewhere (0.1 x 0.2 x
// 101 m^2 = 2 m^2), as fittings on a solar array's node do; with wide_kink_part_fraction only
// where the panel is at most that fraction of the node.
TEST(ProjectedAreaBudget, a_wide_kink_goes_where_its_swept_outline_is_small_against_the_node) {
  auto panel = [](bool with_plate) {
    test::MeshBuilder b;
    b.grid(Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0), 4, 0);
    b.v[b.vertex(Vector3d(0.5, 0, 0))] = Vector3d(0.5, -0.4, 0);
    if (with_plate) b.grid(Vector3d(-20, 0, 5), Vector3d(10, 0, 0), Vector3d(0, 10, 0), 1, 0);
    return b.build(1);
  };
  auto kink_kept = [](const Mesh& m) {
    for (int v = 0; v < m.num_vertices(); ++v)
      if (m.V(v, 1) < -0.3) return true;
    return false;
  };
  DecimationOptions capped;
  capped.max_relative_area_change = 0.2;  // the kink's 17 % of the panel's area is not what is tested
  capped.projected_area_budget = 1.0;
  capped.projected_area_cap = 10.0;
  const Eigen::VectorXd ratio = Eigen::VectorXd::Constant(1, 0.95);
  EXPECT_TRUE(kink_kept(decimate_nodes(panel(true), ratio, capped).mesh));  // relative cap alone
  DecimationOptions wide = capped;
  wide.wide_kink_area_fraction = 0.1;
  EXPECT_TRUE(kink_kept(decimate_nodes(panel(false), ratio, wide).mesh));
  const DecimationResult plate = decimate_nodes(panel(true), ratio, wide);
  EXPECT_FALSE(kink_kept(plate.mesh));
  EXPECT_LT(plate.mesh.num_faces(), decimate_nodes(panel(true), ratio, capped).mesh.num_faces());
  // ... and only on a part small against its node: the 1.2 m^2 panel is 1.2 % of the node's 101 m^2
  wide.wide_kink_part_fraction = 0.03;
  EXPECT_FALSE(kink_kept(decimate_nodes(panel(true), ratio, wide).mesh));
  wide.wide_kink_part_fraction = 0.01;
  EXPECT_TRUE(kink_kept(decimate_nodes(panel(true), ratio, wide).mesh));
  wide.wide_kink_part_fraction = 1.0;
  wide.projected_area_cap = 0;  // without the cap nothing tracks the node's projected area
  EXPECT_TRUE(kink_kept(decimate_nodes(panel(true), ratio, wide).mesh));
  wide.wide_kink_area_fraction = -1;
  EXPECT_THROW(decimate_nodes(panel(true), ratio, wide), InvalidInput);
}

TEST(ProjectedAreaBudget, bad_fold_limit_is_refused_before_any_work) {
  const Mesh fan = rim_fan({{1, 0, 0}, {0, -0.4, 0}, {-1, 0, 0}});
  DecimationOptions o;
  o.max_fold_deg = 200;
  EXPECT_THROW(decimate_nodes(fan, one_face_less(fan), o), InvalidInput);
  o.max_fold_deg = 120;
  o.projected_area_budget = -1;
  EXPECT_THROW(decimate_nodes(fan, one_face_less(fan), o), InvalidInput);
}

}  // namespace
}  // namespace thermodec
