// Validation of the whole chain (view factors -> loads -> network) against closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "environment/test_models.h"
#include "thermodec/environment/orbit.h"
#include "thermodec/thermal/simulate_model.h"

using namespace thermodec;
using namespace thermodec::testing;
using V3 = Eigen::Vector3d;

namespace {
constexpr double kSigma = kStefanBoltzmann_W_per_m2_K4;
}

TEST(Validation, isothermal_cube_in_fixed_sun_matches_closed_form) {
  // Convex cube, one node, sun along +X: absorbs alpha S (1 m^2 projected), emits from 6 m^2:
  // T = (alpha S / (6 eps sigma))^(1/4). Every ray of a convex body escapes, the lit face is
  // unshadowed: exact up to the 2.7 K sink (T^4 + 2.7^4) and round-off.
  ThermalModel model = model_with({"cube"}, {{"paint", 0.6, 0.8}});
  add_cube(model.mesh, 0.5);
  model.environment.type = EnvironmentType::fixed_sun;
  model.environment.sun_direction = V3::UnitX();
  model.environment.solar_flux_W_per_m2 = 1361.0;
  const SimulationResult r = simulate_model(model);
  const double expected = std::pow(0.6 * 1361.0 / (6 * 0.8 * kSigma) + std::pow(2.7, 4), 0.25);
  ASSERT_EQ(r.times_s.size(), 1);
  EXPECT_NEAR(r.temperature_K(0, 0), expected, 1e-9 * expected);
  EXPECT_NEAR(expected, 234.04, 0.01);  // (0.6 x 1361 / (4.8 sigma))^(1/4)
}

TEST(Validation, thin_two_sided_plate_facing_the_sun_matches_closed_form) {
  // Two-sided sheet: absorbs alpha S A on its front, emits from both sides:
  // T = (alpha S / (2 eps sigma))^(1/4).
  ThermalModel model = model_with({"plate"}, {{"cells", 0.9, 0.85}});
  add_quad(model.mesh, V3(-1, -1, 0), V3(2, 0, 0), V3(0, 2, 0), 0, 0, /*back material*/ 0, 3);
  model.environment.type = EnvironmentType::fixed_sun;
  model.environment.sun_direction = V3::UnitZ();
  model.environment.solar_flux_W_per_m2 = 1361.0;
  const SimulationResult r = simulate_model(model);
  const double expected = std::pow(0.9 * 1361.0 / (2 * 0.85 * kSigma) + std::pow(2.7, 4), 0.25);
  EXPECT_NEAR(r.temperature_K(0, 0), expected, 1e-9 * expected);
}

TEST(Validation, periodic_orbit_transient_balances_energy_within_0_1_percent) {
  // Six-node box in a 500 km orbit with conduction, dissipation and an arithmetic node: over
  // the converged orbit, absorbed = emitted + stored (+ to fixed nodes) within 0.1 %.
  ThermalModel model = model_with({"px", "mx", "py", "my", "pz", "mz"}, {{"paint", 0.3, 0.8}, {"mli", 0.4, 0.05}});
  add_cube(model.mesh, 0.5, {0, 1, 2, 3, 4, 5});
  model.nodes[3].material = 1;
  for (int f = 0; f < model.mesh.num_faces(); ++f)
    if (model.mesh.face_node[f] == 3) model.mesh.face_material[f] = 1;
  model.nodes[2].capacitance_J_per_K = 0.0;  // arithmetic
  model.nodes[0].power_W = 30.0;
  for (int i = 0; i < 6; ++i)
    for (int j = i + 1; j < 6; ++j) model.conductances.push_back({i, j, 0.5});
  model.environment.type = EnvironmentType::orbit;
  model.environment.altitude_km = 500.0;
  model.environment.inclination_deg = 51.6;
  model.analysis.type = AnalysisType::transient_orbit;
  model.analysis.steps_per_orbit = 48;
  model.analysis.orbits = 5;
  const SimulationResult r = simulate_model(model);
  ASSERT_TRUE(r.transient);
  EXPECT_LE(r.periodicity_residual_K, 1e-3);
  EXPECT_LT(r.energy.relative_imbalance(), 1e-3);
  // Over a periodic orbit nothing is stored; absorbed energy is what the loads say. The solver
  // integrates the loads interpolated between the 48 positions with the sun switched at the
  // exact eclipse entry and exit, so it differs from the positions' rectangle sum by at most
  // the direct-sun power over one position interval at each of the two switches.
  EXPECT_LT(std::abs(r.energy.stored_J), 1e-3 * r.energy.absorbed_J);
  const double period = orbit_period_s(500.0);
  const double absorbed = (r.loads.total_W().sum() / 48 + 30.0) * period;
  const double sun_W = (r.loads.solar_W + r.loads.reflected_solar_W).colwise().sum().maxCoeff();
  EXPECT_NEAR(r.energy.absorbed_J, absorbed, 2.0 * sun_W * period / 48);
}

namespace {
// A two-sided panel (solar cells in front, white paint behind) facing the velocity in a nadir
// orbit: its direct sun turns edge-on twice per orbit (a kink of max(0, n . s) on each side),
// and the orbit has an eclipse. Simulated with `positions` load positions.
SimulationResult panel_in_orbit(int positions, const ExternalLoadSettings& loads = {}) {
  ThermalModel model = model_with({"panel"}, {{"cells", 0.9, 0.85}, {"paint", 0.2, 0.9}});
  add_quad(model.mesh, V3(0, -1, -0.5), V3(0, 0, 1), V3(0, 2, 0), 0, 0, /*back material*/ 1, 2);
  model.nodes[0].capacitance_J_per_K = 4500.0;  // the sample's wings
  model.environment.type = EnvironmentType::orbit;
  model.environment.altitude_km = 700.0;
  model.environment.inclination_deg = 98.0;
  model.environment.raan_deg = 90.0;
  model.environment.day_of_year = 172;
  model.analysis.type = AnalysisType::transient_orbit;
  model.analysis.steps_per_orbit = positions;
  model.analysis.orbits = 5;
  ModelSimulationSettings settings;
  settings.loads = loads;
  return simulate_model(model, settings);
}

// Largest |T_a - T_b| at a's positions, b sampled `ratio` times as finely (same seed).
double max_difference_at_positions(const SimulationResult& a, const SimulationResult& b, int ratio) {
  double d = 0.0;
  for (int k = 0; k < a.times_s.size(); ++k) d = std::max(d, std::abs(a.temperature_K(0, k) - b.temperature_K(0, ratio * k)));
  return d;
}
}  // namespace

TEST(Validation, orbit_sampling_knots_and_their_error_estimate_against_a_20x_position_reference) {
  // 60 positions plus the eclipse edges and the panel's edge-on instant against 1200 positions
  // (same seed): the knots take out the kinks (the bare 60 positions are > 4x further off), what
  // is left is the curvature of the loads between positions, which the Richardson estimate
  // (summary.orbit_sampling_error_K, from every other position) measures within a factor 2.
  // Without the knots the kinks make the interpolation first order locally and the estimate
  // understates; the 1200-position run's own estimate is small.
  const SimulationResult fine = panel_in_orbit(1200);
  const SimulationResult knots = panel_in_orbit(60);
  ExternalLoadSettings plain;
  plain.eclipse_edges = false;
  plain.kink_knot_threshold_K = 0.0;
  const SimulationResult bare = panel_in_orbit(60, plain);
  ASSERT_TRUE(knots.loads.has_knots());
  EXPECT_GE(knots.loads.knot_times_s.size(), 3);  // two edges, a sunlit kink at least
  const double with_knots = max_difference_at_positions(knots, fine, 20);
  const double without = max_difference_at_positions(bare, fine, 20);
  std::printf("60 positions: with knots %.4f K (estimate %.4f K), without %.4f K (estimate %.4f K); 1200: estimate %.4f K\n",
              with_knots, knots.orbit_sampling_error_K, without, bare.orbit_sampling_error_K, fine.orbit_sampling_error_K);
  EXPECT_GT(without, 4.0 * with_knots);
  EXPECT_GT(knots.orbit_sampling_error_K, 0.5 * with_knots);
  EXPECT_LT(knots.orbit_sampling_error_K, 2.0 * with_knots);
  EXPECT_LT(fine.orbit_sampling_error_K, 0.01);
}
