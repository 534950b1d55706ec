// The reflected-sunlight cap (DecimationOptions::face_reflected_flux_W_per_m2, reflection_cap):
// a collapse may not move reflected sunlight from lit faces onto dark ones beyond the node's
// cap, whatever its area and projected area do (a flat plate keeps both exactly).
#include <gtest/gtest.h>

#include <vector>

#include "decimation/test_meshes.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/decimate_nodes.h"

namespace thermodec {
namespace {

// A flat 1 m x 1 m plate, one node of 8 x 8 x 2 faces; the half x < 0.5 lit.
Mesh plate() {
  test::MeshBuilder b;
  b.grid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), 8, 0);
  return b.build(1);
}

std::vector<double> half_lit(const Mesh& m, double lit_W_per_m2) {
  std::vector<double> q(2 * m.num_faces(), 0.0);
  for (int f = 0; f < m.num_faces(); ++f) {
    const double x = (m.V(m.F(f, 0), 0) + m.V(m.F(f, 1), 0) + m.V(m.F(f, 2), 0)) / 3.0;
    if (x < 0.5) q[2 * f] = lit_W_per_m2;
  }
  return q;
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

TEST(ReflectionCap, keeps_lit_and_dark_faces_apart_on_a_flat_plate) {
  const Mesh m = plate();
  const Eigen::VectorXd ratio = Eigen::VectorXd::Constant(1, 0.9);
  DecimationOptions plain;
  const DecimationResult without = decimate_nodes(m, ratio, plain);
  ASSERT_GT(straddling(without.mesh), 0) << "the geometric decimation merges across the lit edge";

  DecimationOptions capped = plain;
  capped.face_reflected_flux_W_per_m2 = half_lit(m, 100.0);
  capped.reflection_cap = 1e-12;  // no reflected power may move
  const DecimationResult with = decimate_nodes(m, ratio, capped);
  EXPECT_EQ(straddling(with.mesh), 0);
  EXPECT_GT(with.mesh.num_faces(), without.mesh.num_faces());
  EXPECT_LT(with.mesh.num_faces(), m.num_faces() / 2) << "each half still decimates";
  EXPECT_GT(with.nodes[0].blocked_edges[static_cast<int>(CollapseBlock::reflected_sunlight)], 0);

  // A uniformly lit plate moves no reflected power: the cap changes nothing.
  capped.face_reflected_flux_W_per_m2.assign(2 * m.num_faces(), 100.0);
  const DecimationResult uniform = decimate_nodes(m, ratio, capped);
  EXPECT_EQ(uniform.mesh.F, without.mesh.F);
  EXPECT_EQ(uniform.mesh.V, without.mesh.V);
}

TEST(ReflectionCap, rejects_fluxes_of_the_wrong_size_or_sign) {
  const Mesh m = plate();
  const Eigen::VectorXd ratio = Eigen::VectorXd::Constant(1, 0.5);
  DecimationOptions o;
  o.face_reflected_flux_W_per_m2.assign(m.num_faces(), 1.0);  // one per face, not two
  EXPECT_THROW(decimate_nodes(m, ratio, o), InvalidInput);
  o.face_reflected_flux_W_per_m2.assign(2 * m.num_faces(), 1.0);
  o.face_reflected_flux_W_per_m2[3] = -1.0;
  EXPECT_THROW(decimate_nodes(m, ratio, o), InvalidInput);
}

}  // namespace
}  // namespace thermodec
