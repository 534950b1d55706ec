// The reflected-sunlight cap (DecimationOptions::reflection, reflection_cap): a collapse may not
// merge lit faces with dark ones that see a neighbour differently past the neighbour's cap,
// whatever the plate's area and projected area do (a flat plate keeps both exactly).
#include <gtest/gtest.h>

#include <vector>

#include "decimation/test_meshes.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/decimate_nodes.h"

namespace thermodec {
namespace {

// A flat 1 m x 1 m plate, node 0 of 8 x 8 x 2 faces, and a small neighbour (node 1) apart.
Mesh plate() {
  test::MeshBuilder b;
  b.grid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), 8, 0);
  b.grid(Eigen::Vector3d(3, 0, 1), Eigen::Vector3d(0.2, 0, 0), Eigen::Vector3d(0, 0.2, 0), 1, 1);
  return b.build(2);
}

double centre_x(const Mesh& m, int f) { return (m.V(m.F(f, 0), 0) + m.V(m.F(f, 1), 0) + m.V(m.F(f, 2), 0)) / 3.0; }

// The plate's fronts: `lit` [W/m^2] reflected where x < 0.5, `dark` elsewhere; they see node 1
// with F = view_lit where x < 0.5, view_dark elsewhere; node 1 absorbs 100 W.
DecimationOptions::ReflectionData half_lit(const Mesh& m, double lit, double dark, double view_lit, double view_dark) {
  DecimationOptions::ReflectionData r;
  r.view_start.push_back(0);
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 2; ++k) {
      const bool front_of_plate = k == 0 && m.face_node[f] == 0;
      const bool left = centre_x(m, f) < 0.5;
      r.flux_W_per_m2.push_back(front_of_plate ? (left ? lit : dark) : 0.0);
      if (front_of_plate) r.view_node.push_back(1), r.view_fraction.push_back(left ? view_lit : view_dark);
      r.view_start.push_back(static_cast<int>(r.view_node.size()));
    }
  r.node_absorbed_W = {1000.0, 100.0};
  return r;
}

// Coarse faces with corners on both sides of the lit edge x = 0.5.
int straddling(const Mesh& m) {
  int n = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    bool lo = false, hi = false;
    for (int k = 0; k < 3; ++k) lo |= m.V(m.F(f, k), 0) < 0.5 - 1e-9, hi |= m.V(m.F(f, k), 0) > 0.5 + 1e-9;
    n += lo && hi;
  }
  return n;
}

TEST(ReflectionCap, keeps_lit_and_dark_faces_apart_where_they_see_a_neighbour_differently) {
  const Mesh m = plate();
  const Eigen::VectorXd ratio = (Eigen::VectorXd(2) << 0.9, 0.0).finished();
  DecimationOptions plain;
  const DecimationResult without = decimate_nodes(m, ratio, plain);
  ASSERT_GT(straddling(without.mesh), 0) << "the geometric decimation merges across the lit edge";

  DecimationOptions capped = plain;
  capped.reflection = half_lit(m, 100.0, 0.0, 0.1, 0.8);
  capped.reflection_cap = 1e-12;  // the light reaching node 1 may not move
  const DecimationResult with = decimate_nodes(m, ratio, capped);
  EXPECT_EQ(straddling(with.mesh), 0);
  EXPECT_GT(with.mesh.num_faces(), without.mesh.num_faces());
  EXPECT_LT(with.nodes[0].faces_after, 128 / 2) << "each half still decimates";
  EXPECT_GT(with.nodes[0].blocked_edges[static_cast<int>(CollapseBlock::reflected_sunlight)], 0);

  // Uniform light, or a uniform view of node 1: merging moves nothing node 1 receives.
  for (const auto& data : {half_lit(m, 100.0, 100.0, 0.1, 0.8), half_lit(m, 100.0, 0.0, 0.5, 0.5)}) {
    capped.reflection = data;
    const DecimationResult uniform = decimate_nodes(m, ratio, capped);
    EXPECT_EQ(uniform.mesh.F, without.mesh.F);
    EXPECT_EQ(uniform.mesh.V, without.mesh.V);
  }
}

TEST(ReflectionCap, rejects_inconsistent_data) {
  const Mesh m = plate();
  const Eigen::VectorXd ratio = (Eigen::VectorXd(2) << 0.5, 0.0).finished();
  DecimationOptions o;
  o.reflection = half_lit(m, 1.0, 1.0, 0.5, 0.5);
  o.reflection.flux_W_per_m2.pop_back();  // one flux short
  EXPECT_THROW(decimate_nodes(m, ratio, o), InvalidInput);
  o.reflection = half_lit(m, 1.0, 1.0, 0.5, 0.5);
  o.reflection.flux_W_per_m2[3] = -1.0;
  EXPECT_THROW(decimate_nodes(m, ratio, o), InvalidInput);
  o.reflection = half_lit(m, 1.0, 1.0, 0.5, 0.5);
  o.reflection.view_node[0] = 2;  // no such node
  EXPECT_THROW(decimate_nodes(m, ratio, o), InvalidInput);
}

}  // namespace
}  // namespace thermodec
