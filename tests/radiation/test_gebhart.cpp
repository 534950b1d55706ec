// Gebhart factors and node couplings against two-surface closed forms (Howell, Menguc &
// Siegel, "Thermal Radiation Heat Transfer", 6th ed., sec. 6.3: net exchange in a two-surface
// enclosure, q = sigma (T1^4 - T2^4) A1 / (1/eps1 + A1/A2 (1/eps2 - 1))).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "test_meshes.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/bare_mesh_cleanup.h"
#include "thermodec/radiation/gebhart_factors.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/surface_sides.h"

using namespace thermodec;
using namespace thermodec::test;

namespace {

// Two sides, one per node, seeing each other with factor f (the rest goes to space).
FaceViewFactors two_sides(double f, double area) {
  FaceViewFactors vf;
  vf.sides.face = Eigen::Vector2i(0, 1);
  vf.sides.is_back = Eigen::Vector2i(0, 0);
  vf.sides.node = Eigen::Vector2i(0, 1);
  vf.sides.material = Eigen::Vector2i(0, 0);
  vf.sides.area_m2 = Eigen::Vector2d(area, area);
  vf.sides.key = {1, 2};
  vf.F.resize(2, 2);
  vf.F.insert(0, 1) = f;
  vf.F.insert(1, 0) = f;
  vf.F.makeCompressed();
  vf.to_space = Eigen::Vector2d(1 - f, 1 - f);
  vf.rays_per_side = 1000000;
  return vf;
}

}  // namespace

TEST(Gebhart, infinite_grey_parallel_plates_match_closed_form) {
  const double e1 = 0.3, e2 = 0.8, A = 2.0;
  const FaceViewFactors vf = two_sides(1.0, A);
  const Eigen::Vector2d eps(e1, e2);
  const GebhartFactors gb = gebhart_factors(vf, eps, node_groups(vf.sides, 2), 3);
  EXPECT_NEAR(gb.B(0, 1), e2 / (1 - (1 - e1) * (1 - e2)), 1e-10);  // sum of the reflection series
  EXPECT_LT(gb.max_closure_error, 1e-10);
  const NodeCouplings c = aggregate_couplings(vf, eps, gb, 2);
  EXPECT_NEAR(c.radiative_couplings_m2(0, 1), A / (1 / e1 + 1 / e2 - 1), 1e-9);
  EXPECT_NEAR(c.radiative_couplings_m2(1, 0), A / (1 / e1 + 1 / e2 - 1), 1e-9);
  EXPECT_NEAR(c.to_space_couplings_m2[0], 0.0, 1e-12);
}

TEST(Gebhart, finite_plates_with_uniform_radiosity_match_closed_form) {
  // Two facing sides with view factor f, the rest to space: summing the reflection series,
  // B12 = f eps2 / (1 - rho1 rho2 f^2) and B11 = f rho2 f eps1 / (1 - rho1 rho2 f^2).
  const double f = 0.2, e1 = 0.5, e2 = 0.7;
  const FaceViewFactors vf = two_sides(f, 1.0);
  const GebhartFactors gb = gebhart_factors(vf, Eigen::Vector2d(e1, e2), node_groups(vf.sides, 2), 3);
  const double tol = GebhartSettings{}.tolerance;  // per entry of B
  EXPECT_NEAR(gb.B(0, 1), f * e2 / (1 - (1 - e1) * (1 - e2) * f * f), tol);
  EXPECT_NEAR(gb.B(0, 0), f * (1 - e2) * f * e1 / (1 - (1 - e1) * (1 - e2) * f * f), tol);
  EXPECT_NEAR(gb.B.row(0).sum(), 1.0, 3.0 * tol);
  GebhartSettings tight;
  tight.tolerance = 1e-12;
  EXPECT_NEAR(gebhart_factors(vf, Eigen::Vector2d(e1, e2), node_groups(vf.sides, 2), 3, tight).B(0, 1),
              f * e2 / (1 - (1 - e1) * (1 - e2) * f * f), 1e-12);
  // The same factors from F in uncompressed storage (as Eigen leaves it after insert()).
  FaceViewFactors loose = vf;
  loose.F.uncompress();
  ASSERT_FALSE(loose.F.isCompressed());
  EXPECT_EQ(gebhart_factors(loose, Eigen::Vector2d(e1, e2), node_groups(vf.sides, 2), 3).B, gb.B);
}

TEST(Gebhart, concentric_grey_spheres_match_two_surface_enclosure) {
  Mesh mesh;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  sphere(0.5, false, 10, 20, V, F);
  append_part(mesh, V, F, "inner");
  sphere(1.0, true, 14, 28, V, F);
  append_part(mesh, V, F, "outer");
  ThermalModel m = model_of(mesh, 0.6);
  m.materials.push_back(Material{"outer", 0.5, 0.3});
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (mesh.face_node[f] == 1) m.mesh.face_material[f] = 1;
  const NodeCouplings c = radiative_couplings(m, m.radiation);
  const double A1 = c.area_m2[0], A2 = c.area_m2[1];
  const double exact = A1 / (1 / 0.6 + A1 / A2 * (1 / 0.3 - 1));
  const double se = c.radiative_couplings_standard_error(0, 1);
  EXPECT_NEAR(c.radiative_couplings_m2(0, 1), exact, 5 * se) << "se " << se;
  EXPECT_LT(std::abs(c.radiative_couplings_m2(0, 1) / exact - 1), 0.01);
  EXPECT_EQ(c.to_space_couplings_m2[0], 0.0);
  // Closure: everything node 0 emits (A1 eps1) is absorbed by node 0 or node 1.
  EXPECT_NEAR(c.radiative_couplings_m2.row(0).sum(), A1 * 0.6, 1e-6 * A1);
  EXPECT_LT(c.diagnostics.gebhart_closure_error, 1e-8);
  EXPECT_LT(c.diagnostics.coupling_closure_error * A1 * 0.6, 5 * se) << "symmetrising moved rows by noise only";
}

TEST(Gebhart, highly_reflective_closed_box_converges_and_closes) {
  // eps = 0.05: the plain Neumann series needs ~450 sweeps; the Krylov start must give the
  // same answer (checked against the series alone, from zero), also from a warm start.
  Mesh mesh;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  box({0, 0, 0}, {1, 2, 0.5}, true, 3, V, F);
  append_part(mesh, V, F, "box");
  mesh.node_names = {"a", "b", "c"};
  for (int f = 0; f < mesh.num_faces(); ++f) mesh.face_node[f] = (f / 18) % 3;
  const ThermalModel m = model_of(mesh, 0.05, 1.0, 400);
  const NodeCouplings c = radiative_couplings(m, m.radiation);
  EXPECT_LT(c.diagnostics.gebhart_closure_error, 1e-8);
  EXPECT_LT(c.diagnostics.coupling_closure_error, 1e-2);
  EXPECT_LE(c.diagnostics.gebhart_iterations, 10);
  EXPECT_TRUE(c.radiative_couplings_m2.isApprox(c.radiative_couplings_m2.transpose()));

  const RayScene scene(m.mesh);
  const SurfaceSides sides = surface_sides(m);
  const FaceViewFactors vf = face_view_factors(scene, sides, m.radiation);
  const Eigen::VectorXd eps = side_emissivity(m, sides);
  const GebhartFactors krylov = gebhart_factors(vf, eps, node_groups(sides, 3), 4);
  const RowMatrixXd zero = RowMatrixXd::Zero(sides.size(), 5);
  GebhartSettings sweeps_only;
  sweeps_only.krylov_start = false;
  const GebhartFactors series = gebhart_factors(vf, eps, node_groups(sides, 3), 4, sweeps_only, &zero);
  EXPECT_GT(series.iterations, 100);
  const double tol = GebhartSettings{}.tolerance;  // each solve within it of the exact B
  EXPECT_LT((krylov.B - series.B).cwiseAbs().maxCoeff(), 2.0 * tol);
  // A warm start (a trial's: the reference's solution, here perturbed) takes the Krylov path too.
  const RowMatrixXd near = series.B + RowMatrixXd::Constant(sides.size(), 5, 1e-3);
  const GebhartFactors warm = gebhart_factors(vf, eps, node_groups(sides, 3), 4, {}, &near);
  EXPECT_LE(warm.iterations, 10);
  EXPECT_LT((warm.B - series.B).cwiseAbs().maxCoeff(), 2.0 * tol);
}

TEST(Gebhart, coupling_standard_errors_are_not_optimistic) {
  // Spread of GR_12 over 8 seeds vs the mean reported standard error (parallel plates, grey).
  Mesh mesh;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  grid({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 3, 3, V, F);
  append_part(mesh, V, F, "bottom");
  grid({0, 0, 0.5}, {0, 1, 0}, {1, 0, 0}, 3, 3, V, F);
  append_part(mesh, V, F, "top");
  std::vector<double> gr;
  double se = 0;
  for (int seed = 1; seed <= 8; ++seed) {
    const ThermalModel m = model_of(mesh, 0.6, 1.0, 256, seed);
    const NodeCouplings c = radiative_couplings(m, m.radiation);
    gr.push_back(c.radiative_couplings_m2(0, 1));
    se += c.radiative_couplings_standard_error(0, 1) / 8;
  }
  double mean = 0, var = 0;
  for (double g : gr) mean += g / gr.size();
  for (double g : gr) var += (g - mean) * (g - mean) / (gr.size() - 1);
  EXPECT_LT(std::sqrt(var), 2.0 * se) << "spread " << std::sqrt(var) << " reported " << se;
}

TEST(Gebhart, rejects_absorptivity_outside_unit_interval) {
  const FaceViewFactors vf = two_sides(0.5, 1.0);
  EXPECT_THROW(gebhart_factors(vf, Eigen::Vector2d(0.0, 0.5), node_groups(vf.sides, 2), 3), InvalidInput);
  EXPECT_THROW(gebhart_factors(vf, Eigen::Vector2d(0.5, 0.5), Eigen::Vector2i(0, 7), 3), InvalidInput);
}

TEST(Gebhart, coupling_to_space_of_a_flat_node_comes_from_closure_with_the_symmetrised_couplings) {
  // A flat plate (no self-view) under a better-sampled parallel plate: its coupling to space is
  // A eps minus its couplings to the other plate, whose estimate comes mostly from the other
  // plate's rays. Over 8 seeds that estimate spreads less than the plate's own raw estimate
  // (sum of A_s eps_s B(s, space) over its sides), and its reported error is not optimistic.
  Mesh mesh;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  grid({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 3, 3, V, F);
  append_part(mesh, V, F, "bottom");
  grid({0, 0, 0.5}, {0, 1, 0}, {1, 0, 0}, 3, 3, V, F);
  append_part(mesh, V, F, "top");
  std::vector<double> closed, raw;
  double se = 0;
  for (int seed = 1; seed <= 8; ++seed) {
    ThermalModel m = model_of(mesh, 0.6, 1.0, 256, seed);
    m.radiation.min_rays_per_node = 2000;
    m.nodes[1].sampling_boost.ir = 16.0;
    const RayScene scene(m.mesh);
    const SurfaceSides sides = surface_sides(m);
    const FaceViewFactors vf = face_view_factors(scene, sides, m.radiation);
    const Eigen::VectorXd eps = side_emissivity(m, sides);
    const GebhartFactors gb = gebhart_factors(vf, eps, node_groups(sides, 2), 3);
    const NodeCouplings c = aggregate_couplings(vf, eps, gb, 2);
    double r = 0.0;
    for (int s = 0; s < sides.size(); ++s)
      if (sides.node[s] == 0) r += sides.area_m2[s] * eps[s] * gb.B(s, 3);
    raw.push_back(r);
    closed.push_back(c.to_space_couplings_m2[0]);
    se += c.to_space_couplings_standard_error[0] / 8;
    EXPECT_NEAR(c.to_space_couplings_m2[0] + c.radiative_couplings_m2(0, 1) + c.radiative_couplings_m2(0, 0),
                c.area_m2[0] * 0.6, 1e-9);
  }
  auto spread = [](const std::vector<double>& x) {
    double mean = 0, var = 0;
    for (double g : x) mean += g / x.size();
    for (double g : x) var += (g - mean) * (g - mean) / (x.size() - 1);
    return std::sqrt(var);
  };
  // Expected ratio ~1/4 (the other plate's 16x rays); 8 draws put a sample sd within ~0.5-1.5x
  // of the true one, so 0.6 leaves room on both sides.
  EXPECT_LT(spread(closed), 0.6 * spread(raw)) << "closure " << spread(closed) << " raw " << spread(raw);
  EXPECT_LT(spread(closed), 2.0 * se) << "spread " << spread(closed) << " reported " << se;
}

namespace {
// A plate inside a closed box (one-sided, outward) facing down onto a plate under the box:
// the inner plate's rays leave through the back of the box's floor and land on the lower
// plate, whose rays stop on the floor's front. The pair is not reciprocal by geometry, whatever
// the ray counts (the Juno bus floor inside a larger closed part). A third plate beside, off
// both their views.
Mesh plate_inside_a_box() {
  Mesh mesh;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  box({-1, -1, 0}, {1, 1, 2}, false, 2, V, F);
  append_part(mesh, V, F, "box");
  grid({-0.5, -0.5, 0.5}, {0, 1, 0}, {1, 0, 0}, 2, 2, V, F);  // normal -z
  append_part(mesh, V, F, "inner");
  grid({-1, -1, -0.25}, {2, 0, 0}, {0, 2, 0}, 3, 3, V, F);  // normal +z
  append_part(mesh, V, F, "lower");
  grid({4, 4, -1}, {0, 1, 0}, {1, 0, 0}, 2, 2, V, F);  // normal -z: sees neither
  append_part(mesh, V, F, "beside");
  return mesh;
}

NodeCouplings couplings_of(const ThermalModel& m) {
  const RayScene scene(m.mesh);
  const SurfaceSides sides = surface_sides(m);
  const FaceViewFactors vf = face_view_factors(scene, sides, m.radiation);
  const Eigen::VectorXd eps = side_emissivity(m, sides);
  const int n = static_cast<int>(m.nodes.size());
  return aggregate_couplings(vf, eps, gebhart_factors(vf, eps, node_groups(sides, n), n + 1), n);
}
}  // namespace

TEST(Gebhart, pairs_not_reciprocal_by_geometry_are_counted_and_reciprocal_ones_are_not) {
  // The inner plate sees the lower one through the box floor (thousands of hits), the lower
  // plate never sees the inner one: counted. Two plates facing each other in the open: not.
  ThermalModel m = model_of(plate_inside_a_box(), 1.0, 1.0, 64, 3);
  m.radiation.min_rays_per_node = 20000;
  const NodeCouplings c = couplings_of(m);
  EXPECT_GT(c.diagnostics.back_hits_on_one_sided, 0);
  EXPECT_GE(c.diagnostics.non_reciprocal_pairs, 1);
  Mesh open;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  grid({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 3, 3, V, F);
  append_part(open, V, F, "bottom");
  grid({0, 0, 0.5}, {0, 1, 0}, {1, 0, 0}, 3, 3, V, F);
  append_part(open, V, F, "top");
  ThermalModel r = model_of(open, 1.0, 1.0, 64, 3);
  r.radiation.min_rays_per_node = 20000;
  r.nodes[1].sampling_boost.ir = 16.0;
  EXPECT_EQ(couplings_of(r).diagnostics.non_reciprocal_pairs, 0);
}

TEST(Gebhart, a_closed_part_with_a_plate_inside_radiates_into_its_cavity_and_every_pair_is_reciprocal) {
  // The bare-mesh cleanup finds the box hollow (something is inside) and makes its walls
  // two-sided: the inner plate's rays stop on the inside of the floor, and with every surface
  // black and no escape from the box, both sides of the inner plate (1 m^2 each) deliver all
  // they emit to the box: GR(inner, box) = 2 m^2, GR(inner, lower) = 0.
  const BareMeshCleanupResult cleaned = cleanup_bare_mesh(plate_inside_a_box());
  EXPECT_EQ(cleaned.report.enclosing_shells, 1);
  ThermalModel m = model_of(cleaned.mesh, 1.0, 1.0, 64, 3);
  m.radiation.min_rays_per_node = 20000;
  ASSERT_EQ(m.nodes.size(), 4u);
  ASSERT_EQ(m.nodes[1].name, "inner");
  const NodeCouplings c = couplings_of(m);
  EXPECT_EQ(c.diagnostics.back_hits_on_one_sided, 0);
  EXPECT_EQ(c.diagnostics.non_reciprocal_pairs, 0);
  EXPECT_EQ(c.radiative_couplings_m2(1, 2), 0.0);
  EXPECT_EQ(c.radiative_couplings_m2(1, 3), 0.0);
  const double se = c.radiative_couplings_standard_error(0, 1);
  EXPECT_GT(se, 0.0);
  EXPECT_NEAR(c.radiative_couplings_m2(0, 1), 2.0, 4.0 * se + 1e-12);
}

namespace {

// A strip of n sides, each seeing its neighbours up to 3 places away (a sparse F, as on a
// large craft where a side sees a few dozen of thousands), in 4 groups.
FaceViewFactors strip(int n) {
  FaceViewFactors vf;
  vf.sides.face = Eigen::VectorXi::LinSpaced(n, 0, n - 1);
  vf.sides.is_back = Eigen::VectorXi::Zero(n);
  vf.sides.node = Eigen::VectorXi::LinSpaced(n, 0, n - 1).unaryExpr([n](int s) { return 4 * s / n; });
  vf.sides.material = Eigen::VectorXi::Zero(n);
  vf.sides.area_m2 = Eigen::VectorXd::Ones(n);
  for (int s = 0; s < n; ++s) vf.sides.key.push_back(static_cast<std::uint64_t>(s + 1));
  vf.F.resize(n, n);
  vf.to_space = Eigen::VectorXd::Ones(n);
  for (int s = 0; s < n; ++s)
    for (int d = -3; d <= 3; ++d)
      if (d != 0 && s + d >= 0 && s + d < n) {
        const double f = 0.04 / std::abs(d) + 0.001 * ((s * 7 + d) % 5);
        vf.F.insert(s, s + d) = f;
        vf.to_space[s] -= f;
      }
  vf.F.makeCompressed();
  vf.rays_per_side = 1000000;
  return vf;
}

// The rounds as gebhart_factors documents them, every row of F scanned in every round
// (no Krylov start: max rho <= 0.6 here).
RowMatrixXd rounds_scanning_every_row(const FaceViewFactors& vf, const Eigen::VectorXd& a, const Eigen::VectorXi& group,
                                      int G, const RowMatrixXd& start, double tolerance) {
  const int S = vf.sides.size(), C = G + 1;
  const Eigen::VectorXd rho = (1.0 - a.array()).matrix();
  RowMatrixXd E = RowMatrixXd::Zero(S, C);
  for (int s = 0; s < S; ++s) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, s); it; ++it)
      E(s, group[it.col()]) += it.value() * a[it.col()];
    E(s, G) = vf.to_space[s];
  }
  const double threshold = tolerance * std::max(1e-3, 1.0 - rho.maxCoeff());
  RowMatrixXd X = start, R(S, C);
  Eigen::VectorXd row_max(S);
  auto residual = [&] {
    for (int s = 0; s < S; ++s) {
      R.row(s) = E.row(s) - X.row(s);
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, s); it; ++it) {
        const double w = it.value() * rho[it.col()];
        if (w != 0.0)
          for (int c = 0; c < C; ++c) R(s, c) += w * X(it.col(), c);
      }
      row_max[s] = R.row(s).cwiseAbs().maxCoeff();
    }
  };
  residual();
  bool fresh = true;
  for (;;) {
    if (row_max.maxCoeff() <= threshold && !fresh) {
      residual();
      fresh = true;
    }
    if (row_max.maxCoeff() <= threshold) break;
    std::vector<int> slot(S, -1);
    RowMatrixXd P(S, C);
    int n = 0;
    for (int s = 0; s < S; ++s)
      if (row_max[s] > threshold) {
        P.row(n) = R.row(s);
        X.row(s) += P.row(n);
        R.row(s).setZero();
        row_max[s] = 0.0;
        slot[s] = n++;
      }
    for (int t = 0; t < S; ++t) {
      bool taken = false;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, t); it; ++it) {
        const int k = slot[it.col()];
        if (k < 0) continue;
        taken = true;
        const double w = it.value() * rho[it.col()];
        if (w != 0.0)
          for (int c = 0; c < C; ++c) R(t, c) += w * P(k, c);
      }
      if (taken) row_max[t] = R.row(t).cwiseAbs().maxCoeff();
    }
    fresh = false;
  }
  return X;
}

}  // namespace

TEST(Gebhart, a_warm_start_pushing_a_few_rows_gives_the_bits_of_rounds_over_every_row) {
  // A trial's solve: the reference's solution with a few rows off (a change near sides
  // 100-105); the rounds push only the rows over the threshold, and must give the bits of the
  // rounds as documented, written out plainly (every row of F scanned per round).
  const int n = 400;
  const FaceViewFactors vf = strip(n);
  Eigen::VectorXd a(n);
  for (int s = 0; s < n; ++s) a[s] = 0.45 + 0.1 * ((s * 13) % 7) / 7.0;
  const Eigen::VectorXi group = node_groups(vf.sides, 4);
  const GebhartFactors exact = gebhart_factors(vf, a, group, 4);
  RowMatrixXd near = exact.B;
  for (int s = 100; s < 106; ++s) near.row(s) *= 1.02;
  const GebhartFactors warm = gebhart_factors(vf, a, group, 4, {}, &near);
  const RowMatrixXd scanned = rounds_scanning_every_row(vf, a, group, 4, near, GebhartSettings{}.tolerance);
  EXPECT_GT(warm.iterations, 1);
  EXPECT_EQ(warm.B.rows(), scanned.rows());
  EXPECT_TRUE((warm.B.array() == scanned.array()).all()) << (warm.B - scanned).cwiseAbs().maxCoeff();
  EXPECT_LT((warm.B - exact.B).cwiseAbs().maxCoeff(), 2.0 * GebhartSettings{}.tolerance);
  // From scratch (every row pushed at first) too.
  const RowMatrixXd direct = gebhart_factors(vf, a, group, 4, {}, nullptr).B;
  RowMatrixXd E = RowMatrixXd::Zero(n, 5);
  for (int s = 0; s < n; ++s) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, s); it; ++it)
      E(s, group[it.col()]) += it.value() * a[it.col()];
    E(s, 4) = vf.to_space[s];
  }
  EXPECT_TRUE((direct.array() == rounds_scanning_every_row(vf, a, group, 4, E, GebhartSettings{}.tolerance).array()).all());
}
