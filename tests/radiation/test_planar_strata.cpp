// Planar control variates (radiation/planar_strata.h): the closed-form triangle-to-polygon view
// factor against Howell's catalogue, and the regression estimate of view-factor rows: exact
// where nothing hides a flat node, unbiased where something does, rows closed, deterministic.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "analytic.h"
#include "test_meshes.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/polygon_view_factor.h"
#include "thermodec/radiation/radiative_couplings.h"

using namespace thermodec;
using namespace thermodec::test;

namespace {

// Area mean over the unit square (two triangles, emitting along n) of the view factor to `p`.
double square_to_polygon(const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                         const Eigen::Vector3d& n, const std::vector<Eigen::Vector3d>& p) {
  return 0.5 * (triangle_to_polygon_view_factor(o, o + u, o + u + v, n, p) +
                triangle_to_polygon_view_factor(o, o + u + v, o + v, n, p));
}

Mesh plates(int n, const Eigen::Vector3d& c1, const Eigen::Vector3d& u1, const Eigen::Vector3d& v1,
            const Eigen::Vector3d& c2, const Eigen::Vector3d& u2, const Eigen::Vector3d& v2) {
  Mesh m;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  grid(c1, u1, v1, n, n, V, F);
  append_part(m, V, F, "a");
  grid(c2, u2, v2, n, n, V, F);
  append_part(m, V, F, "b");
  return m;
}

NodeCouplings couplings(const ThermalModel& model, bool strata, std::uint64_t seed) {
  RadiationSettings rs = model.radiation;
  rs.planar_strata = strata;
  rs.seed = seed;
  return radiative_couplings(model, rs);
}

}  // namespace

TEST(PolygonViewFactor, parallel_and_perpendicular_squares_match_the_catalogue) {
  const std::vector<Eigen::Vector3d> top{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  EXPECT_NEAR(square_to_polygon({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, top), parallel_rectangles(1, 1, 1), 1e-7);
  const std::vector<Eigen::Vector3d> wall{{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}};
  // Sharing an edge: the integrand is singular along it, the adaptive rule refines there.
  EXPECT_NEAR(square_to_polygon({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, wall), perpendicular_rectangles(1, 1, 1),
              2e-5);
  // Behind the emitter: nothing; half behind: the front half (clipped), here by symmetry.
  const std::vector<Eigen::Vector3d> below{{0, 0, -1}, {1, 0, -1}, {1, 1, -1}, {0, 1, -1}};
  EXPECT_EQ(square_to_polygon({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, below), 0.0);
}

TEST(PlanarStrata, an_unhidden_flat_node_is_seen_exactly_and_rows_still_close) {
  // Perpendicular squares sharing an edge (C-14) and parallel ones (C-11): each node is the
  // other's only partner, nothing between.
  const ThermalModel perp =
      model_of(plates(6, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}), 1.0, 1.0, 512);
  const ThermalModel par =
      model_of(plates(6, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}), 1.0, 1.0, 512);
  // Exact for the geometry the rays start from: origins are lifted 1e-5 x the coordinate
  // magnitude off their face (sampling::make_emitter), which moves F by up to 2.3e-6 here.
  const NodeCouplings plain = couplings(par, false, 1);
  const NodeCouplings b1 = couplings(par, true, 1);
  for (std::uint64_t seed : {1, 2, 3}) {
    const NodeCouplings a = couplings(perp, true, seed), b = couplings(par, true, seed);
    EXPECT_NEAR(a.view_factors(0, 1), perpendicular_rectangles(1, 1, 1), 2e-5) << seed;
    EXPECT_NEAR(b.view_factors(0, 1), parallel_rectangles(1, 1, 1), 1e-5) << seed;
    EXPECT_NEAR(b.view_factors(0, 1), b1.view_factors(0, 1), 1e-12) << seed;  // no seed left in it
    EXPECT_NEAR(b.to_space[0], 1.0 - b.view_factors(0, 1), 1e-6) << seed;     // the row closes
    // The reported error follows the estimator: only the "one ray" floor is left.
    EXPECT_LT(b.radiative_couplings_standard_error(0, 1), 0.1 * plain.radiative_couplings_standard_error(0, 1)) << seed;
  }
  // Plain counts miss by their noise.
  EXPECT_GT(std::abs(plain.view_factors(0, 1) - parallel_rectangles(1, 1, 1)), 1e-5);
}

TEST(PlanarStrata, a_partly_hidden_node_stays_unbiased) {
  // Parallel squares with a small plate between them, off-centre and tilted (not parallel to
  // either): the control sees the whole square, the rays find the blocker.
  Mesh m = plates(4, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0});
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  grid({0.2, 0.3, 0.4}, {0.4, 0, 0.1}, {0, 0.35, 0}, 2, 2, V, F);
  append_part(m, V, F, "blocker", 0);  // two-sided: it blocks from both sides
  const ThermalModel model = model_of(m, 1.0, 1.0, 2048);
  double mean_cv = 0.0, mean_plain = 0.0, var_cv = 0.0, var_plain = 0.0;
  const int K = 12;
  for (int k = 1; k <= K; ++k) {
    const double x = couplings(model, true, k).view_factors(0, 1), y = couplings(model, false, k).view_factors(0, 1);
    mean_cv += x / K;
    mean_plain += y / K;
    var_cv += x * x / K;
    var_plain += y * y / K;
  }
  var_cv -= mean_cv * mean_cv;
  var_plain -= mean_plain * mean_plain;
  EXPECT_NEAR(mean_cv, mean_plain, 5.0 * std::sqrt((var_cv + var_plain) / K));
  EXPECT_LT(var_cv, var_plain);  // the hidden share's variance only
  EXPECT_LT(mean_cv, parallel_rectangles(1, 1, 1) - 0.005);  // the blocker is seen
}

TEST(PlanarStrata, results_are_bit_identical_for_any_thread_count) {
  const ThermalModel model =
      model_of(plates(6, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}), 0.8, 1.0, 512);
  NodeCouplings one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = couplings(model, true, 7);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = couplings(model, true, 7);
  }
  EXPECT_EQ(one.radiative_couplings_m2, two.radiative_couplings_m2);
  EXPECT_EQ(one.to_space_couplings_m2, two.to_space_couplings_m2);
  EXPECT_EQ(one.radiative_couplings_standard_error, two.radiative_couplings_standard_error);
}
