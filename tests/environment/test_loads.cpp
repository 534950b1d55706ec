#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <cstdio>
#include <numeric>
#include <vector>

#include "environment/test_models.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/environment/orbit.h"
#include "thermodec/mesh/face_geometry.h"
#include "thermodec/nodes/load_model.h"

using namespace thermodec;
using namespace thermodec::testing;
using V3 = Eigen::Vector3d;

namespace {
std::string fs_sample() { return std::string(THERMODEC_SOURCE_DIR) + "/sample_models/satellite/model.json"; }
Loads loads_of(const ThermalModel& model, const ExternalLoadSettings& s = {}, bool reflections = true) {
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  const FaceViewFactors vf = face_view_factors(scene, sides, model.radiation);
  return external_loads(model, scene, sides, reflections ? &vf : nullptr, s);
}
}  // namespace

TEST(CubeLoads, each_face_sees_the_earth_as_the_closed_form_plate_factors) {
  // Cube, one node per face, nadir attitude: +Z faces the Earth centre. F of a plate facing
  // the Earth is (R / r)^2; of a plate facing away, 0. The cube is convex: no self-shadowing.
  ThermalModel model = model_with({"px", "mx", "py", "my", "pz", "mz"}, {{"paint", 0.5, 0.8}});
  add_cube(model.mesh, 0.5, {0, 1, 2, 3, 4, 5});
  model.environment.type = EnvironmentType::orbit;
  model.environment.altitude_km = 600.0;
  model.analysis.steps_per_orbit = 12;
  const Loads l = loads_of(model);
  const double r = orbit_radius_m(600.0), F_nadir = std::pow(kEarthRadius_m / r, 2);
  // Earth IR is constant in a nadir attitude; Sobol on a smooth integrand: ~1/N error.
  EXPECT_NEAR(l.earth_ir_W(4, 0), 0.8 * 237.0 * 1.0 * F_nadir, 0.8 * 237.0 * F_nadir * 2e-3);
  EXPECT_EQ(l.earth_ir_W(5, 0), 0.0);
  // A side wall (normal horizontal) at altitude h: F = (1/pi)(atan(1/sqrt(H^2-1)) - sqrt(H^2-1)/H^2), H = r/R.
  const double H = r / kEarthRadius_m, x = std::sqrt(H * H - 1.0);
  const double F_side = (std::atan(1.0 / x) - x / (H * H)) / 3.14159265358979323846;
  for (int n : {0, 1, 2, 3}) EXPECT_NEAR(l.earth_ir_W(n, 0), 0.8 * 237.0 * F_side, 0.8 * 237.0 * F_side * 5e-3) << n;
}

TEST(EarthViewFactor, unobstructed_closed_form_matches_quadrature_over_the_earth_cap_at_every_tilt) {
  // (1/pi) int_cap max(0, n . w) dw by the midpoint rule in (cos a, phi) about the Earth
  // direction: 1200 x 1200 cells resolve the horizon kink to ~1e-6 of the nadir value.
  const double r = orbit_radius_m(700.0), H = r / kEarthRadius_m;
  const double cos_half = std::sqrt(1.0 - 1.0 / (H * H)), pi = 3.14159265358979323846;
  for (double tilt_deg : {0.0, 30.0, 60.0, 65.0, 75.0, 90.0, 100.0, 110.0, 120.0, 130.0}) {
    const double t = tilt_deg * pi / 180.0;
    const V3 n(std::sin(t), 0.0, std::cos(t));  // Earth along +Z
    const int M = 1200;
    double f = 0.0;
    for (int i = 0; i < M; ++i) {
      const double c = 1.0 - (i + 0.5) / M * (1.0 - cos_half), sn = std::sqrt(1.0 - c * c);
      for (int j = 0; j < M; ++j) {
        const double phi = 2.0 * pi * (j + 0.5) / M;
        f += std::max(0.0, n.dot(V3(sn * std::cos(phi), sn * std::sin(phi), c)));
      }
    }
    f *= (1.0 - cos_half) * 2.0 * pi / (double(M) * M) / pi;
    EXPECT_NEAR(unobstructed_earth_view_factor(std::cos(t), r), f, 2e-6 / (H * H)) << tilt_deg << " deg";
  }
  EXPECT_EQ(unobstructed_earth_view_factor(-1.0, r), 0.0);
  EXPECT_THROW(unobstructed_earth_view_factor(1.0, 0.5 * kEarthRadius_m), InvalidInput);
}

TEST(EarthViewFactor, unobstructed_sides_get_the_closed_form_exactly_whatever_the_seed) {
  // The ray estimate only measures the blocked share (ratio estimator): a lone plate, tilted
  // so the horizon cuts the Earth, has no sampling noise at all.
  ThermalModel model = model_with({"plate"}, {{"paint", 0.5, 0.8}});
  const double t = 1.2;  // rad from nadir
  add_quad(model.mesh, V3(0, 0, 0), V3(std::cos(t), 0, -std::sin(t)), V3(0, 1, 0), 0, 0);
  const double r = orbit_radius_m(700.0);
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  for (std::uint64_t seed : {1u, 2u}) {
    const Eigen::VectorXd F = earth_view_factors(scene, sides, V3::UnitZ(), r, 256, seed);
    for (int s = 0; s < sides.size(); ++s) {
      const V3 normal = sides.is_back[s] ? V3(-std::sin(t), 0, -std::cos(t)) : V3(std::sin(t), 0, std::cos(t));
      EXPECT_NEAR(F[s], unobstructed_earth_view_factor(normal.z(), r), 1e-12) << s << " seed " << seed;
    }
  }
}

TEST(EarthViewFactor, nadir_facing_plate_matches_closed_form_and_a_blocker_hides_the_earth) {
  ThermalModel model = model_with({"plate", "shield"}, {{"paint", 0.5, 0.8}});
  // Plate at z = 0 facing +Z (the Earth in nadir body axes).
  add_quad(model.mesh, V3(-0.5, -0.5, 0), V3(1, 0, 0), V3(0, 1, 0), 0, 0, -1, 2);
  const double r = orbit_radius_m(500.0);
  {
    const RayScene scene(model.mesh);
    const SurfaceSides sides = surface_sides(model);
    const Eigen::VectorXd F = earth_view_factors(scene, sides, V3::UnitZ(), r, 1024, 7);
    for (int s = 0; s < sides.size(); ++s) EXPECT_NEAR(F[s], std::pow(kEarthRadius_m / r, 2), 1e-3) << s;
    const Eigen::VectorXd F_away = earth_view_factors(scene, sides, -V3::UnitZ(), r, 1024, 7);
    EXPECT_EQ(F_away.sum(), 0.0);
  }
  // A large shield 1 cm below the Earth-facing side (facing the plate) hides nearly all of
  // the Earth: what is left is the sliver past the shield's edge (< 1e-3 of the cap).
  add_quad(model.mesh, V3(-50, 50, 0.01), V3(100, 0, 0), V3(0, -100, 0), 1, 0);
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  const Eigen::VectorXd F = earth_view_factors(scene, sides, V3::UnitZ(), r, 1024, 7);
  for (int s = 0; s < sides.size(); ++s)
    if (sides.node[s] == 0) EXPECT_LT(F[s], 1e-3) << s;
}

TEST(EarthViewFactor, rasterised_view_matches_brute_force_rays_with_a_fraction_of_their_seed_spread) {
  // A nadir-facing plate (node 0) under a tilted panel (node 1) that hides part of the Earth's
  // cone, differently from each point of the plate. The rasterised view (default) against the
  // cone rays (by_rays), both at 2^14 rays a side (256 raster origins), 8 seeds each: the means
  // agree within the rays' standard error of the mean (4 sigma) plus the grid's discretisation
  // (pixel pitch 3.7 deg at 700 km, its edge error averaged over the origins: < 0.3 % of the
  // cone), and the raster's seed-to-seed spread is under half the rays'.
  ThermalModel model = model_with({"plate", "panel"}, {{"paint", 0.5, 0.8}});
  add_quad(model.mesh, V3(-0.5, -0.5, 0), V3(1, 0, 0), V3(0, 1, 0), 0, 0, -1, 2);
  add_quad(model.mesh, V3(-0.2, -1.0, 0.6), V3(0, 2.0, 0), V3(1.5, 0, 0.9), 1, 0);
  const double r = orbit_radius_m(700.0);
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  const int seeds = 8, rays = 1 << 14;
  Eigen::MatrixXd raster(sides.size(), seeds), by_rays(sides.size(), seeds);
  for (int k = 0; k < seeds; ++k) {
    raster.col(k) = earth_view_factors(scene, sides, V3::UnitZ(), r, rays, k + 1);
    by_rays.col(k) = earth_view_factors(scene, sides, V3::UnitZ(), r, rays, k + 1, kEarthRadius_m, true);
  }
  auto spread = [&](const Eigen::MatrixXd& m, int s) {
    const double mean = m.row(s).mean();
    return std::sqrt((m.row(s).array() - mean).square().sum() / (seeds - 1));
  };
  const double f_open = std::pow(kEarthRadius_m / r, 2);
  double sum_raster = 0.0, sum_rays = 0.0;
  int plate_sides = 0;
  for (int s = 0; s < sides.size(); ++s) {
    if (sides.node[s] != 0 || sides.is_back[s]) continue;
    ++plate_sides;
    const double a = raster.row(s).mean(), b = by_rays.row(s).mean();
    EXPECT_LT(a, 0.95 * f_open) << s;  // partly blocked
    EXPECT_GT(a, 0.05 * f_open) << s;
    EXPECT_NEAR(a, b, 4.0 * spread(by_rays, s) / std::sqrt(double(seeds)) + 3e-3 * f_open) << s;
    sum_raster += spread(raster, s);
    sum_rays += spread(by_rays, s);
  }
  EXPECT_EQ(plate_sides, 8);
  EXPECT_LT(sum_raster, 0.5 * sum_rays);
  std::printf("plate sides' seed-to-seed spread of F: raster %.3g, rays %.3g (sum over sides)\n", sum_raster, sum_rays);
}

TEST(SolarLoads, a_blocker_over_half_a_plate_halves_its_direct_sun) {
  // Fixed sun along +Z. Lower plate (node 0, black) at z = 0; a plate (node 1) at z = 1 covers
  // x < 0. Sobol sampling of a straight shadow edge: error ~ N^-3/4 per face (0.006 at 1024).
  ThermalModel model = model_with({"lower", "blocker"}, {{"black", 1.0, 0.9}});
  add_quad(model.mesh, V3(-1, -1, 0), V3(2, 0, 0), V3(0, 2, 0), 0, 0, -1, 3);
  add_quad(model.mesh, V3(-3, -3, 1), V3(3, 0, 0), V3(0, 6, 0), 1, 0);
  model.environment.type = EnvironmentType::fixed_sun;
  model.environment.sun_direction = V3::UnitZ();
  model.environment.solar_flux_W_per_m2 = 1000.0;
  ExternalLoadSettings s;
  s.sun_rays_per_face = 1024;
  const Loads l = loads_of(model, s, false);
  EXPECT_NEAR(l.solar_W(0, 0), 0.5 * 4.0 * 1000.0, 0.01 * 4000.0);
  EXPECT_NEAR(l.solar_W(1, 0), 18.0 * 1000.0, 1e-9 * 18000.0);  // unshadowed: exact
  EXPECT_EQ(l.earth_ir_W.sum(), 0.0);
}

TEST(SolarLoads, a_shadow_cast_by_a_flat_node_is_exact_with_shadow_controls) {
  // A plate half shadowed under an oblique sun: the blocker's hull projected along the sun
  // covers x < 0 of the plate (the shadow edge through the middle of its middle triangles, so
  // no pilot decides a sliver), so 50 % of it is lit. With the shadow control variates
  // (what simulate samples) each partly lit triangle's points are post-stratified by whether
  // their ray crosses the blocker's hull, whose share of the triangle is exact: no seed is left
  // in the direct sun; without them the shadow edge moves it by its sampling error.
  ThermalModel model = model_with({"lower", "blocker"}, {{"black", 1.0, 0.9}});
  add_quad(model.mesh, V3(-1, -1, 0), V3(2, 0, 0), V3(0, 2, 0), 0, 0, -1, 3);
  add_quad(model.mesh, V3(-3, -3, 1), V3(3.3, 0, 0), V3(0, 6, 0), 1, 0);
  model.environment.type = EnvironmentType::fixed_sun;
  const V3 sun = V3(0.3, 0.2, 1.0).normalized();
  model.environment.sun_direction = sun;
  model.environment.solar_flux_W_per_m2 = 1000.0;
  ExternalLoadSettings s;
  s.sun_rays_per_face = 1024;
  s.planar_shadow_controls = true;
  const double exact = 0.5 * 4.0 * 1000.0 * sun.z();
  double plain_min = 1e300, plain_max = -1e300;
  for (std::uint64_t seed : {1, 2, 3}) {
    s.seed = seed;
    s.planar_shadow_controls = true;
    EXPECT_NEAR(loads_of(model, s, false).solar_W(0, 0), exact, 1e-4 * exact) << seed;
    s.planar_shadow_controls = false;
    const double plain = loads_of(model, s, false).solar_W(0, 0);
    plain_min = std::min(plain_min, plain);
    plain_max = std::max(plain_max, plain);
  }
  EXPECT_GT(plain_max - plain_min, 1e-5 * exact);  // the plain counts do move with the seed (~1.6e-4)
}

TEST(SolarLoads, shadow_sample_error_estimate_is_the_measured_seed_to_seed_spread) {
  // The half-shadowed plate above: Loads::sampling_standard_error_W carries the direct sun's
  // shadow-sample error (sqrt(p (1 - p)) N^-3/4 per partly lit side, scrambled nets on a smooth
  // edge); the fully lit blocker carries none. Over 24 seeds the measured spread of the
  // shadowed plate's direct sun is of the estimate's size (the binomial error would be ~6x it).
  ThermalModel model = model_with({"lower", "blocker"}, {{"black", 1.0, 0.9}});
  add_quad(model.mesh, V3(-1, -1, 0), V3(2, 0, 0), V3(0, 2, 0), 0, 0, -1, 3);
  add_quad(model.mesh, V3(-3, -3, 1), V3(3, 0, 0), V3(0, 6, 0), 1, 0);
  model.environment.type = EnvironmentType::fixed_sun;
  model.environment.sun_direction = V3(0.3, 0.2, 1.0).normalized();
  model.environment.solar_flux_W_per_m2 = 1000.0;
  ExternalLoadSettings s;
  s.sun_rays_per_face = 1024;
  double sum = 0.0, sum2 = 0.0, estimate = 0.0;
  const int seeds = 24;
  for (int k = 1; k <= seeds; ++k) {
    s.seed = static_cast<std::uint64_t>(k);
    const Loads l = loads_of(model, s, false);
    EXPECT_EQ(l.sampling_standard_error_W(1, 0), 0.0);  // fully lit: exact
    ASSERT_GT(l.sampling_standard_error_W(0, 0), 0.0);
    estimate += l.sampling_standard_error_W(0, 0) / seeds;
    sum += l.solar_W(0, 0);
    sum2 += l.solar_W(0, 0) * l.solar_W(0, 0);
  }
  const double spread = std::sqrt(std::max(0.0, sum2 / seeds - (sum / seeds) * (sum / seeds)));
  std::printf("shadowed plate, direct sun over %d seeds: spread %.3g W, estimated %.3g W\n", seeds, spread, estimate);
  EXPECT_GT(spread, estimate / 4.0) << "estimate " << estimate << " W";
  EXPECT_LT(spread, estimate * 4.0) << "estimate " << estimate << " W";
}

TEST(SolarLoads, a_sliver_shadow_on_a_huge_triangle_is_caught_whatever_the_seed) {
  // A 10 m x 10 m plate (two 50 m^2 triangles, like a CAD panel) and a 0.2 m x 0.2 m blocker
  // 1 m above it: a shadow of 0.04 m^2, 1/1250 of its triangle. A fixed 256-point pilot misses
  // it for most seeds (then the side counts as fully lit); the pilot grows to 1/32 of the
  // side's 200 000 samples and catches it for every seed.
  ThermalModel model = model_with({"panel", "blocker"}, {{"black", 1.0, 0.9}});
  add_quad(model.mesh, V3(-5, -5, 0), V3(10, 0, 0), V3(0, 10, 0), 0, 0, -1, 1);
  add_quad(model.mesh, V3(2.9, -1.1, 1), V3(0.2, 0, 0), V3(0, 0.2, 0), 1, 0, -1, 1);
  model.environment.type = EnvironmentType::fixed_sun;
  model.environment.sun_direction = V3::UnitZ();
  model.environment.solar_flux_W_per_m2 = 1000.0;
  ExternalLoadSettings s;
  s.sun_rays_per_face = 256;
  s.sun_min_rays_per_node = 400000;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    s.seed = seed;
    const Loads l = loads_of(model, s, false);
    EXPECT_NEAR(l.solar_W(0, 0), 1000.0 * (100.0 - 0.04), 4.0) << "seed " << seed;
  }
}

TEST(SolarLoads, sunlight_reflected_by_a_grey_plate_reaches_a_black_neighbour_by_the_view_factor) {
  // Perpendicular unit squares sharing an edge: A (z = 0, facing +Z, alpha 0.4) is lit along
  // +Z; B (x = 0, facing +X, black) is edge-on to the sun. B absorbs what A reflects towards
  // it: (1 - alpha_A) S A F_AB, F_AB = 0.2000438 (Hottel; catalogue C-14). B is black, so
  // nothing comes back. Monte Carlo F_AB with 16000 rays per face: ~0.5 % (tolerance 2 %).
  ThermalModel model = model_with({"A", "B"}, {{"grey", 0.4, 0.8}, {"black", 1.0, 0.9}});
  add_quad(model.mesh, V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), 0, 0, -1, 4);
  add_quad(model.mesh, V3(0, 0, 0), V3(0, 1, 0), V3(0, 0, 1), 1, 1, -1, 4);
  model.radiation.rays_per_face = 16000;
  model.environment.type = EnvironmentType::fixed_sun;
  model.environment.sun_direction = V3::UnitZ();
  model.environment.solar_flux_W_per_m2 = 1000.0;
  const Loads l = loads_of(model);
  EXPECT_NEAR(l.solar_W(0, 0), 400.0, 1e-9);
  EXPECT_NEAR(l.solar_W(1, 0), 0.0, 1e-9);
  const double expected = 0.6 * 1000.0 * 0.2000438;
  EXPECT_NEAR(l.reflected_solar_W(1, 0), expected, 0.02 * expected);
  EXPECT_NEAR(l.reflected_solar_W(0, 0), 0.0, 1e-12);  // B reflects nothing back
}

TEST(SolarLoads, reciprocity_cuts_the_seed_to_seed_spread_of_reflected_sunlight_and_keeps_it_unbiased) {
  // The plates above, B's rays 16x as dense as A's (an IR boost): the light A reflects to B,
  // 0.6 S A F_AB, from A's rays alone (plain Monte Carlo) and with reciprocity (the loads: A's
  // estimate of A F_AB combined with B's A F_BA by ray density, ~17x less variance for binomial
  // counts). Over 16 seeds: the spread must fall at least 4x in variance, and both means
  // must stay within 3 standard errors of the mean of the closed form (measured: sd 1.92 W
  // plain, 0.25 W with reciprocity; means 120.32 and 120.01 W against 120.03 W).
  ThermalModel model = model_with({"A", "B"}, {{"grey", 0.4, 0.8}, {"black", 1.0, 0.9}});
  add_quad(model.mesh, V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), 0, 0, -1, 2);
  add_quad(model.mesh, V3(0, 0, 0), V3(0, 1, 0), V3(0, 0, 1), 1, 1, -1, 2);
  model.radiation.rays_per_face = 256;
  model.radiation.min_rays_per_node = 0;
  model.nodes[1].sampling_boost.ir = 16.0;
  model.environment.type = EnvironmentType::fixed_sun;
  model.environment.sun_direction = V3::UnitZ();
  model.environment.solar_flux_W_per_m2 = 1000.0;
  const double expected = 0.6 * 1000.0 * 0.2000438;
  const int runs = 16;
  std::vector<double> plain, reciprocal;
  for (int k = 1; k <= runs; ++k) {
    model.radiation.seed = k;
    const RayScene scene(model.mesh);
    const SurfaceSides sides = surface_sides(model);
    const FaceViewFactors vf = face_view_factors(scene, sides, model.radiation);
    double exchange_m2 = 0.0;  // A F_AB from A's rays
    for (int s = 0; s < sides.size(); ++s)
      if (sides.node[s] == 0)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, s); it; ++it)
          if (sides.node[it.col()] == 1) exchange_m2 += sides.area_m2[s] * it.value();
    plain.push_back(0.6 * 1000.0 * exchange_m2);
    reciprocal.push_back(external_loads(model, scene, sides, &vf, {}).reflected_solar_W(1, 0));
  }
  auto mean = [&](const std::vector<double>& x) { return std::accumulate(x.begin(), x.end(), 0.0) / x.size(); };
  auto var = [&](const std::vector<double>& x) {
    const double m = mean(x);
    double v = 0.0;
    for (double xi : x) v += (xi - m) * (xi - m);
    return v / (x.size() - 1);
  };
  EXPECT_LT(var(reciprocal), var(plain) / 4.0) << "sd plain " << std::sqrt(var(plain)) << " W, reciprocal "
                                               << std::sqrt(var(reciprocal)) << " W";
  EXPECT_NEAR(mean(plain), expected, 3.0 * std::sqrt(var(plain) / runs));
  EXPECT_NEAR(mean(reciprocal), expected, 3.0 * std::sqrt(var(reciprocal) / runs));
}

TEST(OrbitLoads, eclipse_steps_get_no_direct_sun_and_same_seed_is_bit_identical) {
  ThermalModel model = model_with({"box"}, {{"paint", 0.5, 0.8}});
  add_cube(model.mesh, 0.5);
  model.environment.type = EnvironmentType::orbit;
  model.environment.inclination_deg = 51.6;
  model.analysis.steps_per_orbit = 36;
  const Loads a = loads_of(model), b = loads_of(model);
  EXPECT_EQ(a.total_W(), b.total_W());
  int dark = 0;
  for (int k = 0; k < 36; ++k) {
    if (a.in_shadow[k]) {
      ++dark;
      EXPECT_EQ(a.solar_W(0, k), 0.0);
    } else {
      EXPECT_GT(a.solar_W(0, k), 0.0);
    }
  }
  EXPECT_NEAR(dark / 36.0, eclipse_fraction(model.environment), 2.0 / 36);
  // Convex box: projected area of a unit cube is between 1 and sqrt(3) m^2.
  const double S = solar_flux_on_day_W_per_m2(model.environment.day_of_year);
  for (int k = 0; k < 36; ++k)
    if (!a.in_shadow[k]) {
      EXPECT_GE(a.solar_W(0, k), 0.5 * S * 1.0 - 1e-6);
      EXPECT_LE(a.solar_W(0, k), 0.5 * S * std::sqrt(3.0) + 1e-6);
    }
  EXPECT_EQ(a.reflected_solar_W.sum(), 0.0);  // convex: nothing reflects onto itself
}

namespace {
// A 1 m cube, one node per face, inertial attitude on an equatorial 600 km orbit, 4 steps: at
// t = 0 the Earth is along body -X, a quarter orbit later along -Y.
ThermalModel inertial_equatorial_cube() {
  ThermalModel model = model_with({"px", "mx", "py", "my", "pz", "mz"}, {{"paint", 0.5, 0.8}});
  add_cube(model.mesh, 0.5, {0, 1, 2, 3, 4, 5});
  model.environment.type = EnvironmentType::orbit;
  model.environment.attitude = Attitude::inertial;
  model.environment.inclination_deg = 0.0;
  model.environment.altitude_km = 600.0;
  model.analysis.steps_per_orbit = 4;
  return model;
}
}  // namespace

TEST(CubeLoads, inertial_attitude_earth_view_from_escaping_rays_matches_closed_form) {
  // Equatorial orbit, inertial attitude: at t = 0 the spacecraft is on ECI +X, so the Earth is
  // along body -X. The Earth moves in body axes, so the escaping-hemisphere path is used:
  // cosine-weighted Sobol rays, the cone edge a discontinuity: ~N^-3/4 (4096 rays: < 0.5 %).
  const ThermalModel model = inertial_equatorial_cube();
  const Loads l = loads_of(model, {}, false);
  const double r = orbit_radius_m(600.0), H = r / kEarthRadius_m, x = std::sqrt(H * H - 1.0);
  const double F_nadir = 1.0 / (H * H), F_side = (std::atan(1.0 / x) - x / (H * H)) / 3.14159265358979323846;
  const double q = 0.8 * 237.0;
  EXPECT_NEAR(l.earth_ir_W(1, 0), q * F_nadir, 0.01 * q * F_nadir);
  EXPECT_EQ(l.earth_ir_W(0, 0), 0.0);
  for (int n : {2, 3, 4, 5}) EXPECT_NEAR(l.earth_ir_W(n, 0), q * F_side, 0.01 * q * F_side) << n;
  // A quarter orbit later the Earth is along body -Y.
  EXPECT_NEAR(l.earth_ir_W(3, 1), q * F_nadir, 0.01 * q * F_nadir);
}

TEST(CubeLoads, moving_earth_rays_follow_the_per_node_budget) {
  // Inertial attitude (escaping hemisphere rays): the per-node minimum applies as in the nadir
  // case. The cube is convex, so every ray of a side escapes and is kept as a sample.
  const ThermalModel model = inertial_equatorial_cube();
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  for (const int min_per_node : {0, 16 * 256 * 8}) {  // 8 triangles per cube face
    ExternalLoadSettings s;
    s.earth_rays_per_face = 256;
    s.earth_min_rays_per_node = min_per_node;
    LoadSamples samples;
    const Loads l = external_loads(model, scene, sides, nullptr, s, {}, &samples);
    for (int k = 0; k < sides.size(); ++k)
      EXPECT_EQ(samples.earth[k].size(), min_per_node ? 4096u : 256u) << k;
    EXPECT_GT(l.earth_ir_W(1, 0), 0.0);  // -X faces the Earth at t = 0
  }
}

namespace {
// The reduction driver's case: the sample satellite (reference samples recorded), then the
// same craft with only node `name` changed (its free vertices pulled 10 % towards its shared
// ones); the changed region bounds the node before and after.
struct ReuseCase {
  ThermalModel model, trial;
  int node = -1;
  Eigen::AlignedBox3d changed;
  LoadSamples reference;
};
ReuseCase reuse_case(const std::string& name, const ExternalLoadSettings& s, Attitude attitude = Attitude::nadir,
                     AnalysisType analysis = AnalysisType::transient_orbit) {
  ReuseCase c;
  c.model = load_model(fs_sample());
  c.model.environment.attitude = attitude;
  c.model.analysis.type = analysis;
  {
    const RayScene scene(c.model.mesh);
    external_loads(c.model, scene, surface_sides(c.model), nullptr, s, {}, &c.reference);
  }
  const Mesh& mesh = c.model.mesh;
  for (size_t n = 0; n < c.model.nodes.size(); ++n)
    if (c.model.nodes[n].name == name) c.node = static_cast<int>(n);
  std::vector<int> uses(mesh.num_vertices(), 0), node_uses(mesh.num_vertices(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      ++uses[mesh.F(f, k)];
      if (mesh.face_node[f] == c.node) ++node_uses[mesh.F(f, k)];
    }
  Eigen::Vector3d root(0, 0, 0);
  int shared = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (node_uses[v] && node_uses[v] < uses[v]) root += mesh.V.row(v).transpose(), ++shared;
  if (shared > 0) root /= shared;
  c.trial = c.model;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (node_uses[v]) {
      c.changed.extend(Eigen::Vector3d(mesh.V.row(v).transpose()));
      if (node_uses[v] == uses[v]) c.trial.mesh.V.row(v) = (root + 0.9 * (mesh.V.row(v).transpose() - root)).transpose();
      c.changed.extend(Eigen::Vector3d(c.trial.mesh.V.row(v).transpose()));
    }
  return c;
}
// Loads of `trial`, in full and reusing `reference`'s samples outside `changed`.
struct FullAndReused {
  Loads full, incremental;
  LoadReuse reuse;
};
FullAndReused full_and_reused(const ThermalModel& trial, const LoadSamples& reference, const Eigen::AlignedBox3d& changed,
                              const ExternalLoadSettings& s) {
  const RayScene scene(trial.mesh);
  const SurfaceSides sides = surface_sides(trial);
  FullAndReused r;
  r.full = external_loads(trial, scene, sides, nullptr, s);
  r.reuse = LoadReuse{&reference, changed};
  r.incremental = external_loads(trial, scene, sides, nullptr, s, {}, nullptr, &r.reuse);
  return r;
}
ExternalLoadSettings small_budgets() {
  ExternalLoadSettings s;
  s.sun_rays_per_face = 64;
  s.sun_pilot_rays = 16;
  s.earth_rays_per_face = 512;
  s.earth_pilot_rays = 64;
  s.sun_min_rays_per_node = 5000;
  s.earth_min_rays_per_node = 20000;
  return s;
}
}  // namespace

TEST(LoadReuse, trial_with_one_node_changed_equals_a_full_recompute_and_reuses_most_sides) {
  // Loads from the reference's samples for the unaffected sides and rays must equal a full
  // run bit for bit, with the rasterised Earth view (default) and with the Earth cone rays.
  for (const bool by_rays : {false, true}) {
  ExternalLoadSettings s = small_budgets();
  s.earth_view_by_rays = by_rays;
  ReuseCase c = reuse_case("wing_py", s);
  ASSERT_GE(c.node, 0);
  ASSERT_TRUE(c.reference.per_ray);
  const RayScene scene(c.trial.mesh);
  const SurfaceSides sides = surface_sides(c.trial);
  const Loads full = external_loads(c.trial, scene, sides, nullptr, s);
  LoadReuse reuse{&c.reference, c.changed};
  const Loads incremental = external_loads(c.trial, scene, sides, nullptr, s, {}, nullptr, &reuse);
  EXPECT_EQ(incremental.solar_W, full.solar_W);
  EXPECT_EQ(incremental.albedo_W, full.albedo_W);
  EXPECT_EQ(incremental.earth_ir_W, full.earth_ir_W);
  // and so does the Earth rays' sampling error (sides reused whole carry the reference's)
  EXPECT_EQ(incremental.sampling_standard_error_W, full.sampling_standard_error_W);
  // Many shadow evaluations and Earth views are far from the wing (measured: printed below).
  EXPECT_GT(reuse.reused_sun, reuse.total_sun / 2) << reuse.reused_sun << " of " << reuse.total_sun;
  // (the wing's own 400 sides are about a third of the craft's Earth views: never reusable)
  EXPECT_GT(reuse.reused_earth, reuse.total_earth / 3) << reuse.reused_earth << " of " << reuse.total_earth;
  // On the other sides, single rays are reused and the ones crossing the wing traced again;
  // sides none of whose rays can reach the wing's cells are replayed without generating them.
  // (The rasterised view has no rays: its sides are reused whole or computed again.)
  if (by_rays) {
    EXPECT_GT(reuse.reused_earth_rays, 0);
    EXPECT_GT(reuse.earth_sides_replayed_by_cells, 0);
    EXPECT_GT(reuse.traced_earth_rays, 0);
  }
  EXPECT_GT(reuse.reused_sun_rays, 0);
  EXPECT_GT(reuse.traced_sun_rays, 0);
  std::printf("reused %ld of %ld shadow evaluations, %d of %d Earth views; rays reused / traced: sun %ld / %ld, "
              "Earth %ld / %ld\n",
              reuse.reused_sun, reuse.total_sun, reuse.reused_earth, reuse.total_earth, reuse.reused_sun_rays,
              reuse.traced_sun_rays, reuse.reused_earth_rays, reuse.traced_earth_rays);
  // And the change is real: the node's own loads moved.
  const Loads before = [&] {
    const RayScene sc(c.model.mesh);
    return external_loads(c.model, sc, surface_sides(c.model), nullptr, s);
  }();
  EXPECT_NE(before.solar_W.row(c.node), full.solar_W.row(c.node));
  }
}

TEST(LoadReuse, rays_shadowed_by_a_shrunk_body_panel_are_traced_again_and_match_a_full_recompute) {
  // body_pz shrinks: rays it blocked in the reference now pass (or meet something further),
  // exactly the rays the per-ray records must not reuse. Sun and Earth both see it (nadir: +Z
  // faces the Earth), and no Earth view of its neighbours is reusable whole.
  ExternalLoadSettings s = small_budgets();
  s.earth_view_by_rays = true;  // (the Earth cone rays' records)
  ReuseCase c = reuse_case("body_pz", s);
  ASSERT_GE(c.node, 0);
  const RayScene scene(c.trial.mesh);
  const SurfaceSides sides = surface_sides(c.trial);
  const Loads full = external_loads(c.trial, scene, sides, nullptr, s);
  LoadReuse reuse{&c.reference, c.changed};
  const Loads incremental = external_loads(c.trial, scene, sides, nullptr, s, {}, nullptr, &reuse);
  EXPECT_EQ(incremental.solar_W, full.solar_W);
  EXPECT_EQ(incremental.albedo_W, full.albedo_W);
  EXPECT_EQ(incremental.earth_ir_W, full.earth_ir_W);
  // and so does the Earth rays' sampling error (sides reused whole carry the reference's)
  EXPECT_EQ(incremental.sampling_standard_error_W, full.sampling_standard_error_W);
  EXPECT_GT(reuse.reused_earth_rays, reuse.traced_earth_rays) << "most rays miss the panel";
  EXPECT_GT(reuse.traced_earth_rays, 0);
}

TEST(LoadReuse, earth_rays_recorded_with_or_without_their_geometry_give_the_same_trial) {
  // With room, the Earth record keeps each ray's origin and direction (tested as they are);
  // without, a trial generates the rays it tests again. Both must give a full run's loads.
  ExternalLoadSettings with = small_budgets(), without = small_budgets();
  with.earth_view_by_rays = without.earth_view_by_rays = true;
  without.earth_ray_geometry_budget_bytes = 0;
  for (const ExternalLoadSettings* s : {&with, &without}) {
    ReuseCase c = reuse_case("body_pz", *s);
    ASSERT_GE(c.node, 0);
    const RayRecords& rec = c.reference.earth_records;
    ASSERT_FALSE(rec.empty());
    EXPECT_EQ(rec.origin_direction.size(), s == &with ? 6 * rec.sample_index.size() : 0u);
    const FullAndReused r = full_and_reused(c.trial, c.reference, c.changed, *s);
    EXPECT_EQ(r.incremental.albedo_W, r.full.albedo_W);
    EXPECT_EQ(r.incremental.earth_ir_W, r.full.earth_ir_W);
    EXPECT_EQ(r.incremental.sampling_standard_error_W, r.full.sampling_standard_error_W);
    EXPECT_GT(r.reuse.reused_earth_rays, 0);
    EXPECT_GT(r.reuse.traced_earth_rays, 0);
  }
}

// The removed and added triangles of a reuse case (faces with a moved vertex, before and after).
Mesh changed_triangles(const ReuseCase& c) {
  const Mesh& a = c.model.mesh;
  const Mesh& b = c.trial.mesh;
  std::vector<Eigen::Vector3d> corners;
  for (int f = 0; f < a.num_faces(); ++f) {
    bool moved = false;
    for (int k = 0; k < 3; ++k) moved |= a.V.row(a.F(f, k)) != b.V.row(b.F(f, k));
    if (!moved) continue;
    for (const Mesh* m : {&a, &b})
      for (int k = 0; k < 3; ++k) corners.push_back(m->V.row(m->F(f, k)).transpose());
  }
  Mesh m;
  const int n = static_cast<int>(corners.size()) / 3;
  m.V.resize(3 * n, 3);
  m.F.resize(n, 3);
  for (int i = 0; i < 3 * n; ++i) m.V.row(i) = corners[i].transpose();
  for (int f = 0; f < n; ++f) m.F.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
  m.face_node = Eigen::VectorXi::Zero(n);
  m.face_material = Eigen::VectorXi::Constant(n, -1);
  m.face_back_material = Eigen::VectorXi::Constant(n, -1);
  return m;
}

TEST(LoadReuse, the_changed_faces_themselves_reuse_more_and_still_equal_a_full_recompute) {
  // With LoadReuse::changed_faces, sides are tested against the changed triangles (sphere
  // tree) instead of their box: fewer rays traced, the same loads bit for bit. (Single rays
  // that enter the box are traced at once in a candidate this small: ChangeBox::clear_before_tracing.)
  const ExternalLoadSettings s = small_budgets();
  long traced_exact = 0, traced_box_only = 0;
  for (const char* name : {"body_pz", "wing_py", "dish"}) {
    ReuseCase c = reuse_case(name, s);
    ASSERT_GE(c.node, 0) << name;
    const RayScene scene(c.trial.mesh), changed(changed_triangles(c));
    ASSERT_GT(changed.num_traced_faces(), 0) << name;
    const SurfaceSides sides = surface_sides(c.trial);
    const Loads full = external_loads(c.trial, scene, sides, nullptr, s);
    LoadReuse box_only{&c.reference, c.changed};
    external_loads(c.trial, scene, sides, nullptr, s, {}, nullptr, &box_only);
    LoadReuse exact{&c.reference, c.changed, &changed};
    const Loads incremental = external_loads(c.trial, scene, sides, nullptr, s, {}, nullptr, &exact);
    EXPECT_EQ(incremental.solar_W, full.solar_W) << name;
    EXPECT_EQ(incremental.albedo_W, full.albedo_W) << name;
    EXPECT_EQ(incremental.earth_ir_W, full.earth_ir_W) << name;
    EXPECT_GE(exact.reused_sun, box_only.reused_sun) << name;
    EXPECT_GE(exact.reused_earth, box_only.reused_earth) << name;
    EXPECT_LE(exact.traced_sun_rays, box_only.traced_sun_rays) << name;
    EXPECT_LE(exact.traced_earth_rays, box_only.traced_earth_rays) << name;
    traced_exact += exact.traced_sun_rays + exact.traced_earth_rays;
    traced_box_only += box_only.traced_sun_rays + box_only.traced_earth_rays;
    std::printf("%s: rays traced, box only / changed faces: sun %ld / %ld, Earth %ld / %ld\n", name,
                box_only.traced_sun_rays, exact.traced_sun_rays, box_only.traced_earth_rays, exact.traced_earth_rays);
  }
  EXPECT_LT(traced_exact, traced_box_only);
}

TEST(LoadReuse, over_the_record_budget_trials_fall_back_to_side_tests_with_the_same_result) {
  ExternalLoadSettings s = small_budgets();
  s.ray_record_budget_bytes = 1000;  // far too small for the sample
  ReuseCase c = reuse_case("wing_my", s);
  EXPECT_FALSE(c.reference.per_ray);
  EXPECT_TRUE(c.reference.earth_records.empty());
  for (const auto& r : c.reference.sun_records) EXPECT_TRUE(r.empty());
  const RayScene scene(c.trial.mesh);
  const SurfaceSides sides = surface_sides(c.trial);
  const Loads full = external_loads(c.trial, scene, sides, nullptr, s);
  LoadReuse reuse{&c.reference, c.changed};
  const Loads incremental = external_loads(c.trial, scene, sides, nullptr, s, {}, nullptr, &reuse);
  EXPECT_EQ(incremental.solar_W, full.solar_W);
  EXPECT_EQ(incremental.albedo_W, full.albedo_W);
  EXPECT_EQ(incremental.earth_ir_W, full.earth_ir_W);
  // and so does the Earth rays' sampling error (sides reused whole carry the reference's)
  EXPECT_EQ(incremental.sampling_standard_error_W, full.sampling_standard_error_W);
  EXPECT_EQ(reuse.reused_sun_rays + reuse.reused_earth_rays, 0);
  EXPECT_GT(reuse.reused_sun, 0);  // the side tests still work
}

TEST(LoadReuse, inertial_attitude_reuses_hemisphere_rays_and_matches_a_full_recompute) {
  // The Earth moves in body axes: escaping hemisphere rays are recorded and reused per ray.
  ExternalLoadSettings s = small_budgets();
  s.earth_rays_per_face = 256;
  ReuseCase c = reuse_case("dish", s, Attitude::inertial);
  ASSERT_TRUE(c.reference.per_ray);
  const RayScene scene(c.trial.mesh);
  const SurfaceSides sides = surface_sides(c.trial);
  const Loads full = external_loads(c.trial, scene, sides, nullptr, s);
  LoadReuse reuse{&c.reference, c.changed};
  const Loads incremental = external_loads(c.trial, scene, sides, nullptr, s, {}, nullptr, &reuse);
  EXPECT_EQ(incremental.solar_W, full.solar_W);
  EXPECT_EQ(incremental.albedo_W, full.albedo_W);
  EXPECT_EQ(incremental.earth_ir_W, full.earth_ir_W);
  // and so does the Earth rays' sampling error (sides reused whole carry the reference's)
  EXPECT_EQ(incremental.sampling_standard_error_W, full.sampling_standard_error_W);
  EXPECT_GT(reuse.reused_earth_rays, 0);
  EXPECT_GT(reuse.traced_earth_rays, 0);
}

TEST(LoadReuse, decimated_node_trial_keeps_earth_pilot_decisions_and_equals_a_full_recompute) {
  // A decimation (the driver's real trials) moves face spheres: a side far from the change can
  // lose or gain "may be blocked" (the conservative test deciding, with the pilot rays, how
  // many Earth rays it traces). Such a side must not be reused whole. Measured on the sample:
  // boom at ratio 0.64 flipped a dish side, 5e-5 W of albedo apart before the fix.
  ThermalModel model = load_model(fs_sample());
  ExternalLoadSettings s;  // the defaults: the flip needs the per-node budgets
  s.earth_view_by_rays = true;  // (the pilot decisions and per-ray records of the Earth cone rays)
  LoadSamples reference;
  {
    const RayScene scene(model.mesh);
    external_loads(model, scene, surface_sides(model), nullptr, s, {}, &reference);
  }
  int node = -1;
  for (size_t n = 0; n < model.nodes.size(); ++n)
    if (model.nodes[n].name == "boom") node = static_cast<int>(n);
  ASSERT_GE(node, 0);
  Eigen::VectorXd ratios = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.nodes.size()));
  ratios[node] = 0.64;
  ThermalModel trial = model;
  trial.mesh = decimate_nodes(model.mesh, ratios).mesh;
  Eigen::AlignedBox3d changed;  // the node's faces before and after bound what changed
  for (const Mesh* m : {&model.mesh, &trial.mesh})
    for (int f = 0; f < m->num_faces(); ++f)
      if (m->face_node[f] == node)
        for (int k = 0; k < 3; ++k) changed.extend(Eigen::Vector3d(m->V.row(m->F(f, k)).transpose()));
  const FullAndReused r = full_and_reused(trial, reference, changed, s);
  EXPECT_EQ(r.incremental.solar_W, r.full.solar_W);
  EXPECT_EQ(r.incremental.albedo_W, r.full.albedo_W);
  EXPECT_EQ(r.incremental.earth_ir_W, r.full.earth_ir_W);
  EXPECT_GT(r.reuse.reused_earth_rays, 0);
}

TEST(LoadReuse, a_grazing_shadow_ray_traced_again_meets_what_a_full_run_meets) {
  // Embree's packet traversal (coherent streams) can decide a grazing ray differently with
  // other rays in its packet; a trial traces only some of a side's rays again, so its packets
  // differ from a full run's. Measured on the sample: body_px at ratio 0.96, one of 2 278 sun
  // rays of an instrument side at a sun 0.8 deg below the top deck's plane, 4.6 mW apart.
  ThermalModel model = load_model(fs_sample());
  const ExternalLoadSettings s;  // the defaults: the per-node budget gives that side its rays
  LoadSamples reference;
  {
    const RayScene scene(model.mesh);
    external_loads(model, scene, surface_sides(model), nullptr, s, {}, &reference);
  }
  Eigen::VectorXd ratios = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.nodes.size()));
  ratios[0] = 0.96;  // body_px
  ThermalModel trial = model;
  trial.mesh = decimate_nodes(model.mesh, ratios).mesh;
  // What changed: the faces of either mesh that the other does not have (by their corners).
  auto corners = [](const Mesh& m, int f) {
    std::array<double, 9> c;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) c[3 * k + j] = m.V(m.F(f, k), j);
    return c;
  };
  Eigen::AlignedBox3d changed;
  for (const auto& [a, b] : {std::pair{&model.mesh, &trial.mesh}, std::pair{&trial.mesh, &model.mesh}}) {
    std::set<std::array<double, 9>> other;
    for (int f = 0; f < b->num_faces(); ++f) other.insert(corners(*b, f));
    for (int f = 0; f < a->num_faces(); ++f)
      if (!other.count(corners(*a, f)))
        for (int k = 0; k < 3; ++k) changed.extend(Eigen::Vector3d(a->V.row(a->F(f, k)).transpose()));
  }
  ASSERT_FALSE(changed.isEmpty());
  const FullAndReused r = full_and_reused(trial, reference, changed, s);
  EXPECT_EQ(r.incremental.solar_W, r.full.solar_W);
  EXPECT_GT(r.reuse.reused_sun_rays, 0);
  EXPECT_GT(r.reuse.traced_sun_rays, 0);
}

// A steady analysis of an orbit uses the orbit mean of the loads: each shadow pass draws its own
// points, 1/D of them (external_loads.h).
TEST(SteadyShadowPasses, division_is_the_two_thirds_power_of_the_passes_and_keeps_small_counts) {
  EXPECT_EQ(shadow_pass_division(0), 1);
  EXPECT_EQ(shadow_pass_division(1), 1);
  EXPECT_EQ(shadow_pass_division(43), 12);  // 72 positions, 43 sunlit (the NASA meshes' orbit)
  EXPECT_EQ(shadow_pass_division(72), 17);
  const Eigen::VectorXi rays = (Eigen::VectorXi(4) << 256, 1003, 20, 8).finished();
  EXPECT_EQ(shadow_rays_per_pass(rays, 12), (Eigen::VectorXi(4) << 22, 84, 16, 8).finished());
  EXPECT_EQ(shadow_rays_per_pass(rays, 1), rays);
}

namespace {
std::int64_t recorded_sun_rays(const LoadSamples& samples) {
  std::int64_t n = 0;
  for (const RayRecords& r : samples.sun_records)
    if (!r.empty()) n += r.ray_begin.back();
  return n;
}
}  // namespace

namespace {
// The loads of `model` with shadow passes drawing their own points (`own`) and sharing them
// (`shared`), with their samples.
struct OwnAndShared {
  Loads own, shared;
  LoadSamples own_samples, shared_samples;
};
OwnAndShared own_and_shared_points(const ThermalModel& model, const ExternalLoadSettings& own,
                                   const ExternalLoadSettings& shared) {
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  OwnAndShared r;
  r.own = external_loads(model, scene, sides, nullptr, own, {}, &r.own_samples);
  r.shared = external_loads(model, scene, sides, nullptr, shared, {}, &r.shared_samples);
  return r;
}
}  // namespace

TEST(SteadyShadowPasses, orbit_mean_matches_shared_points_within_the_error_with_far_fewer_rays) {
  ThermalModel model = load_model(fs_sample());
  model.analysis.type = AnalysisType::steady;
  ExternalLoadSettings own = small_budgets(), shared = small_budgets();
  own.sun_rays_per_face = shared.sun_rays_per_face = 1024;
  own.sun_pilot_rays = shared.sun_pilot_rays = 1024;
  shared.steady_shadow_passes = false;
  const OwnAndShared r = own_and_shared_points(model, own, shared);
  const Loads &a = r.own, &b = r.shared;
  const LoadSamples &with_own = r.own_samples, &with_shared = r.shared_samples;
  ASSERT_TRUE(with_own.per_ray && with_shared.per_ray);
  // The sample's nadir orbit has 36 sunlit positions of 60: D = 11, 94 of 1024 points a pass.
  EXPECT_LT(recorded_sun_rays(with_own) * 8, recorded_sun_rays(with_shared));
  const Eigen::VectorXd mean_a = a.solar_W.rowwise().mean(), mean_b = b.solar_W.rowwise().mean();
  ASSERT_EQ(a.orbit_mean_standard_error_W.size(), mean_a.size());
  for (Eigen::Index n = 0; n < mean_a.size(); ++n) {
    const double se = std::hypot(a.orbit_mean_standard_error_W[n], b.orbit_mean_standard_error_W[n]);
    EXPECT_LE(std::abs(mean_a[n] - mean_b[n]), 4.0 * se + 1e-9 * std::abs(mean_b[n])) << model.nodes[n].name;
  }
  // The orbit mean's error estimate is not much larger than with every point at every pass.
  EXPECT_LE(a.orbit_mean_standard_error_W.maxCoeff(), 2.0 * b.orbit_mean_standard_error_W.maxCoeff());
}

TEST(SteadyShadowPasses, a_trial_reusing_the_reference_equals_a_full_recompute) {
  const ExternalLoadSettings s = small_budgets();
  ReuseCase c = reuse_case("boom", s, Attitude::nadir, AnalysisType::steady);
  ASSERT_GE(c.node, 0);
  const FullAndReused r = full_and_reused(c.trial, c.reference, c.changed, s);
  EXPECT_EQ(r.incremental.solar_W, r.full.solar_W);
  EXPECT_EQ(r.incremental.sampling_standard_error_W, r.full.sampling_standard_error_W);
  EXPECT_EQ(r.incremental.orbit_mean_standard_error_W, r.full.orbit_mean_standard_error_W);
  EXPECT_GT(r.reuse.reused_sun, 0);
}

TEST(TransientShadowPasses, each_pass_draws_its_own_points_and_the_loads_agree_within_the_error) {
  // The sample's transient nadir orbit: the same N points a pass either way, drawn anew at each
  // pass (the default) or shared by every pass.
  ThermalModel model = load_model(fs_sample());
  ASSERT_EQ(model.analysis.type, AnalysisType::transient_orbit);
  ExternalLoadSettings own = small_budgets(), shared = small_budgets();
  own.sun_rays_per_face = shared.sun_rays_per_face = 256;
  shared.transient_shadow_passes = false;
  const OwnAndShared r = own_and_shared_points(model, own, shared);
  const Loads &a = r.own, &b = r.shared;
  ASSERT_EQ(a.solar_W.cols(), b.solar_W.cols());
  EXPECT_NE(a.solar_W, b.solar_W);  // other points
  // Every step agrees within the two runs' errors; the orbit means within theirs.
  for (Eigen::Index n = 0; n < a.solar_W.rows(); ++n) {
    for (Eigen::Index k = 0; k < a.solar_W.cols(); ++k) {
      const double se = std::hypot(a.sampling_standard_error_W(n, k), b.sampling_standard_error_W(n, k));
      EXPECT_LE(std::abs(a.solar_W(n, k) - b.solar_W(n, k)), 5.0 * se + 1e-9 * std::abs(b.solar_W(n, k)))
          << model.nodes[n].name << " step " << k;
    }
    const double se = std::hypot(a.orbit_mean_standard_error_W[n], b.orbit_mean_standard_error_W[n]);
    EXPECT_LE(std::abs(a.solar_W.row(n).mean() - b.solar_W.row(n).mean()), 4.0 * se + 1e-9) << model.nodes[n].name;
  }
  // Independent passes: the orbit mean's error is at most the shared points' (errors that add
  // as standard deviations there, as variances here).
  for (Eigen::Index n = 0; n < a.orbit_mean_standard_error_W.size(); ++n)
    EXPECT_LE(a.orbit_mean_standard_error_W[n], b.orbit_mean_standard_error_W[n] * (1.0 + 1e-9) + 1e-12)
        << model.nodes[n].name;
}

TEST(OrbitLoads, eclipse_edges_carry_the_sunlit_direct_sun_at_the_exact_switch_instants) {
  // Convex cube, nadir: at an edge the direct sun is alpha S sum_faces A max(0, n . s) with the
  // sun direction of that instant (no self-shadowing), although the spacecraft is at the shadow.
  ThermalModel model = model_with({"box"}, {{"paint", 0.5, 0.8}});
  add_cube(model.mesh, 0.5);
  model.environment.type = EnvironmentType::orbit;
  model.environment.inclination_deg = 51.6;
  model.analysis.steps_per_orbit = 12;
  const Loads l = loads_of(model);
  const double P = orbit_period_s(model.environment.altitude_km);
  const Eigen::VectorXd switches = eclipse_switch_times_s(model.environment, P);
  ASSERT_EQ(switches.size(), 2);
  ASSERT_TRUE(l.has_knots());
  EXPECT_EQ(l.knot_times_s, switches);
  EXPECT_EQ(l.num_steps(), 12);  // the edges do not add positions
  const double S = solar_flux_on_day_W_per_m2(model.environment.day_of_year);
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector3d s = orbit_state(model.environment, switches[e]).sun_direction_body;
    double projected = 0.0;
    for (int k = 0; k < 3; ++k) projected += std::abs(s[k]);  // unit cube faces, both signs of each axis
    EXPECT_NEAR(l.knot_solar_W(0, e), 0.5 * S * projected, 1e-9 * S);
    EXPECT_GT(l.knot_albedo_W(0, e) + l.knot_earth_ir_W(0, e), 0.0);
  }
  ExternalLoadSettings off;
  off.eclipse_edges = false;
  const Loads plain = loads_of(model, off);
  EXPECT_FALSE(plain.has_knots());
  EXPECT_EQ(plain.total_W(), l.total_W());  // the positions' loads do not depend on the edges
}
