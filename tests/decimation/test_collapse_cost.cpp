// The collapse cost (geometric vs radiative ranking) and the decimator's reach report.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "decimation/test_meshes.h"
#include "thermodec/decimation/decimate_nodes.h"

namespace thermodec {
namespace {

// Projected area P(d) = sum_f max(0, N_f . d) [m^2] of node `node` in `ndir` directions
// spread over the sphere (Fibonacci lattice), N_f the face's area vector.
std::vector<double> projected_areas(const Mesh& m, int node, int ndir) {
  std::vector<double> p(ndir, 0.0);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int f = 0; f < m.num_faces(); ++f) {
    if (m.face_node[f] != node) continue;
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    const Eigen::Vector3d n = 0.5 * (b - a).cross(c - a);
    for (int k = 0; k < ndir; ++k) {
      const double z = 1.0 - 2.0 * (k + 0.5) / ndir, r = std::sqrt(1.0 - z * z);
      const Eigen::Vector3d d(r * std::cos(golden * k), r * std::sin(golden * k), z);
      p[k] += std::max(0.0, n.dot(d));
    }
  }
  return p;
}

// Largest change of the projected area over the directions, relative to the node's area.
double worst_projected_area_change(const Mesh& before, const Mesh& after, int node, double area_m2) {
  const auto p0 = projected_areas(before, node, 400), p1 = projected_areas(after, node, 400);
  double worst = 0;
  for (size_t k = 0; k < p0.size(); ++k) worst = std::max(worst, std::abs(p1[k] - p0[k]) / area_m2);
  return worst;
}

// One node: a flat 1 m x 1 m panel in a coarse grid and, apart from it, a small finely
// tessellated sphere (r = 5 cm, like a bolt head or a sensor). Flat-panel collapses leave the
// node's projected area unchanged in every direction; each collapse on the sphere tilts some of
// its faces. The geometric cost only sees the swept volumes, tiny on the small sphere, so it
// coarsens the sphere first; the radiative cost ranks the panel first.
TEST(CollapseCost, radiative_cost_removes_flat_faces_before_ones_that_tilt_area) {
  test::MeshBuilder b;
  b.grid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), 6, 0);
  const int panel_faces = static_cast<int>(b.f.size());
  test::add_sphere(b, Eigen::Vector3d(0.5, 0.5, 0.5), 0.05, 8, 16, 0);
  std::fill(b.node.begin(), b.node.end(), 0);
  const Mesh mesh = b.build(1);
  const int sphere_faces = mesh.num_faces() - panel_faces;
  const Eigen::VectorXd ratio = Eigen::VectorXd::Constant(1, 60.0 / mesh.num_faces());

  DecimationOptions geometric;
  DecimationOptions radiative;
  radiative.collapse_cost = CollapseCostKind::radiative;
  const DecimationResult g = decimate_nodes(mesh, ratio, geometric);
  const DecimationResult r = decimate_nodes(mesh, ratio, radiative);
  ASSERT_TRUE(g.nodes[0].reached);
  ASSERT_TRUE(r.nodes[0].reached);
  EXPECT_EQ(r.mesh.num_faces(), g.mesh.num_faces());  // same budget, another choice of faces

  auto sphere_faces_after = [&](const DecimationResult& d) {
    int n = 0;
    for (int f = 0; f < d.mesh.num_faces(); ++f) n += d.fine_face_of_coarse[f] >= panel_faces;
    return n;
  };
  EXPECT_EQ(sphere_faces_after(r), sphere_faces);  // the panel paid for every removed face
  EXPECT_LT(sphere_faces_after(g), sphere_faces);  // the geometric cost cut into the sphere

  const double area = g.nodes[0].area_before_m2;
  const double worst_g = worst_projected_area_change(mesh, g.mesh, 0, area);
  const double worst_r = worst_projected_area_change(mesh, r.mesh, 0, area);
  // Flat collapses change the projected area by rounding only (coordinates of the panel are
  // exact and stay in its plane).
  EXPECT_LT(worst_r, 1e-12);
  EXPECT_GT(worst_g, 1e3 * worst_r + 1e-9);
}

TEST(CollapseCost, radiative_cost_is_deterministic_and_keeps_the_constraints) {
  const Mesh box = test::subdivided_box(6, true);
  DecimationOptions o;
  o.collapse_cost = CollapseCostKind::radiative;
  const Eigen::VectorXd ratio = Eigen::VectorXd::Constant(6, 0.8);
  const DecimationResult a = decimate_nodes(box, ratio, o), b = decimate_nodes(box, ratio, o);
  EXPECT_TRUE(a.mesh.V == b.mesh.V && a.mesh.F == b.mesh.F);
  for (const auto& s : a.nodes) {
    EXPECT_TRUE(s.reached);
    EXPECT_LE(std::abs(s.relative_area_change()), o.max_relative_area_change);
  }
}

// A curved node under a tight area bound with volume-preserving placement: every collapse
// grows its area until the bound refuses the rest, and the report says so.
TEST(DecimationReach, a_node_stopped_by_its_area_bound_says_so) {
  test::MeshBuilder b;
  test::add_sphere(b, Eigen::Vector3d(0, 0, 0), 1.0, 16, 32, 0);
  const Mesh sphere = b.build(4);
  DecimationOptions o;
  o.max_relative_area_change = 1e-4;
  o.max_relative_volume_change = 0.05;
  o.area_neutral_placement = false;
  const DecimationResult r = decimate_nodes(sphere, Eigen::VectorXd::Constant(4, 0.9), o);
  int stopped_by_area = 0;
  for (const auto& s : r.nodes) {
    ASSERT_FALSE(s.reached);
    stopped_by_area += s.stopped_by() == CollapseBlock::area_bound;
    EXPECT_GT(s.blocked_edges[static_cast<int>(CollapseBlock::area_bound)], 0);
  }
  EXPECT_GE(stopped_by_area, 2);
}

TEST(DecimationReach, a_box_side_of_two_triangles_is_held_by_its_frozen_corners) {
  const Mesh box = test::subdivided_box(1, true);  // 6 nodes of 2 faces, every corner frozen
  const DecimationResult r = decimate_nodes(box, Eigen::VectorXd::Constant(6, 0.5));
  for (const auto& s : r.nodes) {
    EXPECT_FALSE(s.reached);
    EXPECT_EQ(s.stopped_by(), CollapseBlock::frozen_vertices);
    EXPECT_STREQ(collapse_block_name(s.stopped_by()), "frozen_vertices");
  }
  // A node that reaches its target reports nothing.
  const DecimationResult fine = decimate_nodes(test::subdivided_box(4, true), Eigen::VectorXd::Constant(6, 0.5));
  for (const auto& s : fine.nodes) {
    EXPECT_TRUE(s.reached);
    EXPECT_EQ(s.stopped_by(), CollapseBlock::none);
  }
}

}  // namespace
}  // namespace thermodec
