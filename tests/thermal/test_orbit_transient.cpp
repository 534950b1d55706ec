// Orbit transient converged in time: closed-form periodic solution, second order under step
// halving, the error controller's tolerance met, eclipse instants from the orbit geometry.
#include <gtest/gtest.h>

#include <cmath>

#include "thermodec/environment/orbit.h"
#include "thermodec/thermal/orbit_transient.h"
#include "common/small_networks.h"

using namespace thermodec;

namespace {

constexpr double kPi = 3.14159265358979323846;

// One capacitive node conducting to a fixed 280 K node: C dT/dt = Q0 + Q1 sin(w t) - G (T - Tb).
ThermalNetwork single_node(double C, double G) { return test::single_node_to_boundary(C, G, 280.0); }

// Three radiating nodes (heavy, light, arithmetic) with an eclipse from 0.62 P to 0.98 P:
// the sun switches inside load intervals, T^4 makes every step a Newton solve.
struct Eclipsed {
  ThermalNetwork net;
  Loads loads;
  Eigen::VectorXd switches;
};
Eclipsed eclipsed(int S) {
  Eclipsed e;
  const double P = 5668.0;
  ThermalNetwork& n = e.net;
  n.node_names = {"heavy", "light", "arith"};
  n.capacitance_J_per_K = Eigen::Vector3d(20000.0, 300.0, 0.0);
  n.power_W = Eigen::Vector3d(20.0, 0.0, 5.0);
  n.fixed_temperature_K = Eigen::Vector3d::Constant(NAN);
  n.conductance_W_per_K = Eigen::Matrix3d::Zero();
  n.radiative_couplings_m2 = Eigen::Matrix3d::Zero();
  n.conductance_W_per_K(0, 1) = n.conductance_W_per_K(1, 0) = 0.5;
  n.conductance_W_per_K(1, 2) = n.conductance_W_per_K(2, 1) = 0.2;
  n.radiative_couplings_m2(0, 1) = n.radiative_couplings_m2(1, 0) = 0.3;
  n.to_space_couplings_m2 = Eigen::Vector3d(0.5, 0.2, 0.3);
  e.loads = test::zero_external_loads(3, S, P);
  e.switches = Eigen::Vector2d(0.62 * P, 0.98 * P);
  for (int k = 0; k < S; ++k) {
    const double t = k * P / S;
    const bool shadow = t > e.switches[0] && t < e.switches[1];
    e.loads.in_shadow[k] = shadow;
    // Sun on the light node at a varying angle, Earth IR on all.
    if (!shadow) e.loads.solar_W(1, k) = 300.0 * (0.6 + 0.4 * std::cos(2 * kPi * t / P)), e.loads.solar_W(2, k) = 40.0;
    e.loads.earth_ir_W.col(k) = Eigen::Vector3d(10.0, 5.0, 2.0) * (1.0 + 0.3 * std::sin(2 * kPi * t / P));
  }
  return e;
}

}  // namespace

TEST(OrbitTransient, sinusoidal_load_matches_the_closed_form_periodic_solution_within_0_01_K) {
  const double C = 2000.0, G = 1.0, Q0 = 30.0, Q1 = 20.0, P = 5400.0, w = 2 * kPi / P;
  const int S = Analysis{}.steps_per_orbit;  // the default load positions
  Loads loads = test::zero_external_loads(2, S, P);
  for (int k = 0; k < S; ++k) loads.earth_ir_W(0, k) = Q0 + Q1 * std::sin(w * loads.times_s[k]);
  const OrbitTransient ot = orbit_transient(single_node(C, G), loads, Eigen::VectorXd(), OrbitTimeSettings{});
  // Periodic solution: T = Tb + Q0/G + Q1/sqrt(G^2 + (C w)^2) sin(w t - atan(C w / G)).
  const double amp = Q1 / std::hypot(G, C * w), phase = std::atan(C * w / G);
  double worst = 0.0;
  for (int k = 0; k < S; ++k) {
    const double t = loads.times_s[k];
    worst = std::max(worst, std::abs(ot.transient.temperature_K(0, k) - (280.0 + Q0 / G + amp * std::sin(w * t - phase))));
  }
  EXPECT_LE(worst, 0.01) << "amplitude " << amp << " K";
  EXPECT_LE(ot.time_error_K, OrbitTimeSettings{}.time_tolerance_K);
}

TEST(OrbitTransient, halving_every_step_divides_the_error_by_four) {
  const Eclipsed e = eclipsed(72);
  OrbitTimeSettings tight;
  tight.time_tolerance_K = 1e-7;
  tight.max_levels = 12;
  const Eigen::MatrixXd ref = orbit_transient(e.net, e.loads, e.switches, tight).transient.temperature_K;
  std::vector<double> err;
  for (int m : {1, 2, 4}) {
    OrbitTimeSettings s;
    s.substeps = m;
    s.max_levels = 3;  // one extrapolated pair: R = 2 T(2m) - T(m) and its neighbour level
    s.time_tolerance_K = 1e3;
    err.push_back((orbit_transient(e.net, e.loads, e.switches, s).transient.temperature_K - ref).cwiseAbs().maxCoeff());
  }
  // Second order: x4 per halving (3 allows for the higher-order terms at the coarsest grid).
  EXPECT_GT(err[0] / err[1], 3.0) << err[0] << " " << err[1];
  EXPECT_GT(err[1] / err[2], 3.0) << err[1] << " " << err[2];
}

TEST(OrbitTransient, default_controller_meets_its_tolerance_against_a_converged_reference) {
  const Eclipsed e = eclipsed(60);
  OrbitTimeSettings tight;
  tight.time_tolerance_K = 1e-7;
  tight.max_levels = 12;
  const Eigen::MatrixXd ref = orbit_transient(e.net, e.loads, e.switches, tight).transient.temperature_K;
  const OrbitTransient ot = orbit_transient(e.net, e.loads, e.switches, OrbitTimeSettings{});
  const double err = (ot.transient.temperature_K - ref).cwiseAbs().maxCoeff();
  EXPECT_LE(ot.time_error_K, OrbitTimeSettings{}.time_tolerance_K);
  EXPECT_LE(err, OrbitTimeSettings{}.time_tolerance_K);
  EXPECT_GT(ot.time_error_K, 0.1 * err);  // the estimate is not wildly pessimistic either
}

TEST(OrbitTransient, eclipse_switches_span_the_closed_form_eclipse_fraction) {
  Environment env;
  env.altitude_km = 500.0;
  env.day_of_year = 80;
  const double P = orbit_period_s(env.altitude_km);
  const Eigen::VectorXd sw = eclipse_switch_times_s(env, P);
  ASSERT_EQ(sw.size(), 2);
  // Shadow is the arc whose midpoint is in shadow.
  const double mid = 0.5 * (sw[0] + sw[1]);
  const double shadow = orbit_state(env, mid).in_shadow ? sw[1] - sw[0] : P - (sw[1] - sw[0]);
  EXPECT_NEAR(shadow / P, eclipse_fraction(env), 1e-6);
}

TEST(OrbitTransient, orbit_mean_of_a_switched_load_is_the_exact_sunlit_fraction) {
  // 1 W of direct sun whenever sunlit, 36 positions: the mean is the exact sunlit share of the
  // orbit, not the share of sunlit positions (which is off by up to one position, 1/36).
  Environment env;
  env.altitude_km = 700.0;
  env.day_of_year = 172;
  env.inclination_deg = 98.0;
  env.raan_deg = 90.0;
  const double P = orbit_period_s(env.altitude_km);
  const Eigen::VectorXd sw = eclipse_switch_times_s(env, P);
  ASSERT_EQ(sw.size(), 2);
  const int S = 36;
  Loads loads;
  loads.period_s = P;
  loads.times_s = Eigen::VectorXd::LinSpaced(S, 0.0, P * (S - 1) / S);
  loads.solar_W = loads.albedo_W = loads.earth_ir_W = loads.reflected_solar_W = Eigen::MatrixXd::Zero(1, S);
  int dark = 0;
  for (int k = 0; k < S; ++k) {
    loads.in_shadow.push_back(orbit_state(env, loads.times_s[k]).in_shadow);
    dark += loads.in_shadow.back();
    loads.solar_W(0, k) = loads.in_shadow.back() ? 0.0 : 1.0;
  }
  const double exact = 1.0 - eclipse_fraction(env);
  ASSERT_GT(std::abs(1.0 - double(dark) / S - exact), 1e-3);  // the plain mean is off
  EXPECT_NEAR(orbit_mean_loads(loads, sw).solar_W(0, 0), exact, 1e-6);
  // With traced eclipse edges (the same 1 W) the mean is the same.
  loads.knot_times_s = sw;
  loads.knot_solar_W = Eigen::MatrixXd::Ones(1, 2);
  loads.knot_albedo_W = loads.knot_earth_ir_W = loads.knot_reflected_solar_W = Eigen::MatrixXd::Zero(1, 2);
  EXPECT_NEAR(orbit_mean_loads(loads, sw).solar_W(0, 0), exact, 1e-6);
}

TEST(OrbitTransient, sunlit_arc_interpolates_to_its_traced_edges) {
  // A direct sun rising linearly towards each edge: between the last sunlit position and the
  // edge the load is the straight line to the edge's traced value, and zero past it.
  Environment env;
  env.altitude_km = 700.0;
  const double P = orbit_period_s(env.altitude_km);
  const Eigen::VectorXd sw = eclipse_switch_times_s(env, P);
  ASSERT_EQ(sw.size(), 2);
  const int S = 24;
  Loads loads;
  loads.period_s = P;
  loads.times_s = Eigen::VectorXd::LinSpaced(S, 0.0, P * (S - 1) / S);
  loads.solar_W = loads.albedo_W = loads.earth_ir_W = loads.reflected_solar_W = Eigen::MatrixXd::Zero(1, S);
  for (int k = 0; k < S; ++k) {
    loads.in_shadow.push_back(orbit_state(env, loads.times_s[k]).in_shadow);
    if (!loads.in_shadow.back()) loads.solar_W(0, k) = 10.0;
  }
  loads.knot_times_s = sw;
  loads.knot_solar_W = Eigen::MatrixXd::Constant(1, 2, 30.0);
  loads.knot_albedo_W = loads.knot_earth_ir_W = loads.knot_reflected_solar_W = Eigen::MatrixXd::Zero(1, 2);
  const double dt = P / S;
  for (int e = 0; e < 2; ++e) {
    const double t = sw[e];
    const bool entry = !orbit_state(env, t - 1.0).in_shadow;
    // The sunlit neighbour position and a point halfway from it to the edge.
    const double lit = entry ? std::floor(t / dt) * dt : std::ceil(t / dt) * dt;
    Eigen::VectorXd at(3);
    at << 0.5 * (lit + t), entry ? t : t + 1e-6, entry ? t + 1e-6 : t;  // sunlit side, then the shadow side
    const Eigen::MatrixXd q = interpolated_loads_W(loads, at, sw);
    EXPECT_NEAR(q(0, 0), 20.0, 1e-6) << "edge " << e;
    EXPECT_NEAR(q(0, 1), 30.0, 1e-3) << "edge " << e;
    EXPECT_NEAR(q(0, 2), 0.0, 1e-9) << "edge " << e;
  }
}
