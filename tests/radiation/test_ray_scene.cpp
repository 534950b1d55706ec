#include "thermodec/rays/ray_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_meshes.h"

using namespace thermodec;

namespace {
Mesh unit_plate(int n) {
  Mesh m;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  test::grid({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n, n, V, F);
  test::append_part(m, V, F, "plate");
  return m;
}
}  // namespace

TEST(RayScene, hits_the_face_under_the_ray_with_its_distance) {
  const Mesh m = unit_plate(4);
  RayScene scene(m);
  double t = 0;
  const int f = scene.intersect({0.3, 0.6, 2.0}, {0, 0, -1}, 0.0, 1e30, &t);
  ASSERT_GE(f, 0);
  EXPECT_NEAR(t, 2.0, 1e-6);
  // The face found contains the hit point (barycentric test in the plane z = 0).
  const Eigen::Vector2d p(0.3, 0.6);
  Eigen::Matrix2d M;
  const Eigen::Vector2d a = m.V.row(m.F(f, 0)).head<2>(), b = m.V.row(m.F(f, 1)).head<2>(), c = m.V.row(m.F(f, 2)).head<2>();
  M << (b - a), (c - a);
  const Eigen::Vector2d uv = M.inverse() * (p - a);
  EXPECT_GE(uv.minCoeff(), -1e-9);
  EXPECT_LE(uv.sum(), 1 + 1e-9);
  EXPECT_EQ(scene.intersect({0.3, 0.6, 2.0}, {0, 0, 1}, 0.0, 1e30), -1);
  EXPECT_EQ(scene.intersect({0.3, 0.6, 2.0}, {0, 0, -1}, 0.0, 1.5), -1) << "t_far bounds the segment";
  EXPECT_TRUE(scene.occluded({0.3, 0.6, 2.0}, {0, 0, -1}, 0.0, 3.0));
  EXPECT_FALSE(scene.occluded({0.3, 0.6, 2.0}, {0, 0, -1}, 0.0, 1.9));
}

TEST(RayScene, rays_along_shared_edges_do_not_leak_in_robust_mode) {
  // A flat, axis-aligned panel: rays through every vertex and along every shared edge must hit.
  const int n = 8;
  RayScene scene(unit_plate(n));
  int leaks = 0, total = 0;
  for (int i = 1; i < n; ++i)
    for (int k = 0; k <= 40; ++k) {
      const double s = double(i) / n, t = 0.0125 + 0.975 * k / 40.0;
      for (const Eigen::Vector3d o : {Eigen::Vector3d(s, t, 1), Eigen::Vector3d(t, s, 1), Eigen::Vector3d(t, t, 1)}) {
        ++total;
        if (scene.intersect(o, {0, 0, -1}, 0.0, 1e30) < 0) ++leaks;
      }
    }
  EXPECT_EQ(leaks, 0) << "of " << total;
}

TEST(RayScene, zero_area_and_nan_faces_are_kept_out_and_never_hit) {
  Mesh m = unit_plate(1);  // faces 0, 1
  m.V.conservativeResize(m.V.rows() + 3, 3);
  m.V.row(4) << 0.2, 0.2, 0.5;
  m.V.row(5) << 0.4, 0.4, 0.5;  // collinear with 4 and 6: zero area
  m.V.row(6) << 0.6, 0.6, 0.5;
  m.F.conservativeResize(4, 3);
  m.F.row(2) << 4, 5, 6;
  m.F.row(3) << 0, 1, 4;
  m.face_node.setZero(4);
  m.face_material.setZero(4);
  m.face_back_material.setConstant(4, -1);
  Mesh nan_mesh = m;
  nan_mesh.V.conservativeResize(nan_mesh.V.rows() + 1, 3);
  nan_mesh.V.row(7) << std::numeric_limits<double>::quiet_NaN(), 0.5, 0.7;
  nan_mesh.F.row(3) << 4, 6, 7;
  EXPECT_FALSE(is_traceable_face(m, 2));
  EXPECT_FALSE(is_traceable_face(nan_mesh, 3));
  RayScene scene(nan_mesh);
  EXPECT_EQ(scene.num_traced_faces(), 2);
  EXPECT_EQ(scene.num_skipped_faces(), 2);
  const int f = scene.intersect({0.4, 0.4, 2.0}, {0, 0, -1}, 0.0, 1e30);
  EXPECT_TRUE(f == 0 || f == 1) << f;
}

TEST(RayScene, batched_queries_match_single_queries) {
  Mesh m;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  test::sphere(1.0, false, 12, 24, V, F);
  test::append_part(m, V, F, "ball");
  RayScene scene(m);
  std::vector<RayQuery> rays;
  for (int i = 0; i < 1000; ++i) {
    const double a = 0.37 * i, b = 0.011 * i;
    RayQuery q;
    q.origin[0] = 3.0f; q.origin[1] = float(0.9 * std::sin(a)); q.origin[2] = float(0.9 * std::cos(b));
    q.direction[0] = -1.0f; q.direction[1] = float(0.1 * std::cos(a)); q.direction[2] = 0.0f;
    q.t_near = 0.0f;
    q.t_far = (i % 3 == 0) ? 2.5f : 1e30f;
    rays.push_back(q);
  }
  std::vector<int> face;
  std::vector<float> t;
  std::vector<std::uint8_t> blocked;
  scene.intersect(rays, face, &t);
  scene.occluded(rays, blocked);
  int hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto& q = rays[i];
    double ts = 0;
    const int fs = scene.intersect({q.origin[0], q.origin[1], q.origin[2]}, {q.direction[0], q.direction[1], q.direction[2]},
                                   q.t_near, q.t_far, &ts);
    EXPECT_EQ(face[i], fs) << i;
    if (fs >= 0) {
      EXPECT_FLOAT_EQ(t[i], float(ts));
      ++hits;
    }
    EXPECT_EQ(blocked[i] != 0, fs >= 0) << i;
  }
  EXPECT_GT(hits, 300);
}
