#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"
#include "thermodec/thermal/network.h"
#include "thermodec/thermal/steady_state.h"
#include "thermodec/thermal/transient.h"

using namespace thermodec;

namespace {
constexpr double kSigma = kStefanBoltzmann_W_per_m2_K4;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ThermalNetwork network(int n) {
  ThermalNetwork net;
  for (int i = 0; i < n; ++i) net.node_names.push_back("n" + std::to_string(i));
  net.capacitance_J_per_K = Eigen::VectorXd::Zero(n);
  net.power_W = Eigen::VectorXd::Zero(n);
  net.fixed_temperature_K = Eigen::VectorXd::Constant(n, kNaN);
  net.conductance_W_per_K = Eigen::MatrixXd::Zero(n, n);
  net.radiative_couplings_m2 = Eigen::MatrixXd::Zero(n, n);
  net.to_space_couplings_m2 = Eigen::VectorXd::Zero(n);
  return net;
}
void link(ThermalNetwork& net, int i, int j, double gl, double gr) {
  net.conductance_W_per_K(i, j) = net.conductance_W_per_K(j, i) = gl;
  net.radiative_couplings_m2(i, j) = net.radiative_couplings_m2(j, i) = gr;
}
}  // namespace

TEST(SteadyState, heated_node_conducting_to_a_radiator_matches_closed_form) {
  // Node 0 dissipates P and only conducts (GL) to node 1, which radiates to space:
  // T1 = (P / (sigma GRs) + Ts^4)^(1/4), T0 = T1 + P / GL.
  ThermalNetwork net = network(2);
  net.power_W[0] = 50.0;
  link(net, 0, 1, 2.0, 0.0);
  net.to_space_couplings_m2[1] = 0.4;
  const SteadyState ss = steady_state(net, Eigen::VectorXd::Zero(2));
  const double t1 = std::pow(50.0 / (kSigma * 0.4) + std::pow(2.7, 4), 0.25);
  EXPECT_NEAR(ss.temperature_K[1], t1, 1e-9);
  EXPECT_NEAR(ss.temperature_K[0], t1 + 25.0, 1e-9);
}

TEST(SteadyState, conduction_plus_radiation_to_a_fixed_node_balances_the_power) {
  // Node 0 linked to a 250 K boundary node by GL and GR: P = GL dT + sigma GR (T0^4 - T1^4).
  ThermalNetwork net = network(2);
  net.fixed_temperature_K[1] = 250.0;
  link(net, 0, 1, 0.3, 0.8);
  const double t0 = 321.0;
  net.power_W[0] = 0.3 * (t0 - 250.0) + kSigma * 0.8 * (std::pow(t0, 4) - std::pow(250.0, 4));
  const SteadyState ss = steady_state(net, Eigen::VectorXd::Zero(2));
  EXPECT_NEAR(ss.temperature_K[0], t0, 1e-9);
  EXPECT_EQ(ss.temperature_K[1], 250.0);
}

TEST(SteadyState, node_without_path_to_a_sink_is_named_in_the_error) {
  ThermalNetwork net = network(3);
  net.to_space_couplings_m2[0] = 1.0;
  link(net, 0, 1, 1.0, 0.0);
  net.node_names[2] = "floating_box";
  net.power_W[2] = 1.0;
  try {
    steady_state(net, Eigen::VectorXd::Zero(3));
    FAIL() << "expected SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("floating_box"), std::string::npos) << e.what();
  }
}

TEST(SteadyState, radiatively_coupled_cold_start_converges_from_large_loads) {
  // Many nodes in a chain with strong radiation, loads from 0 to 5 kW: Newton + line search.
  const int n = 12;
  ThermalNetwork net = network(n);
  for (int i = 0; i + 1 < n; ++i) link(net, i, i + 1, 0.01, 0.5);
  net.to_space_couplings_m2[n - 1] = 0.05;
  Eigen::VectorXd E = Eigen::VectorXd::Zero(n);
  E[0] = 5000.0;
  const SteadyState ss = steady_state(net, E);
  EXPECT_LT(ss.max_residual_W, 1e-6);
  // Everything leaves through node n-1: sigma GRs (T^4 - Ts^4) = 5000.
  const double t_last = std::pow(5000.0 / (kSigma * 0.05) + std::pow(2.7, 4), 0.25);
  EXPECT_NEAR(ss.temperature_K[n - 1], t_last, 1e-6);
}

TEST(Transient, constant_loads_stay_at_the_steady_state) {
  ThermalNetwork net = network(2);
  net.capacitance_J_per_K << 500.0, 0.0;  // one arithmetic node
  link(net, 0, 1, 1.5, 0.2);
  net.to_space_couplings_m2 << 0.3, 0.1;
  Eigen::MatrixXd loads(2, 36);
  loads.row(0).setConstant(80.0);
  loads.row(1).setConstant(10.0);
  const SteadyState ss = steady_state(net, loads.col(0));
  const PeriodicTransient tr = periodic_transient(net, loads, 5400.0);
  EXPECT_EQ(tr.orbits, 1);
  for (int k = 0; k < 36; ++k) EXPECT_NEAR((tr.temperature_K.col(k) - ss.temperature_K).cwiseAbs().maxCoeff(), 0.0, 1e-7);
}

TEST(Transient, eclipsed_orbit_is_periodic_and_conserves_energy_within_0_1_percent) {
  // Heavy and light nodes, an arithmetic node and a boundary node; square-wave sun.
  ThermalNetwork net = network(4);
  net.capacitance_J_per_K << 20000.0, 300.0, 0.0, 0.0;
  net.fixed_temperature_K[3] = 290.0;
  link(net, 0, 1, 0.5, 0.3);
  link(net, 1, 2, 0.2, 0.1);
  link(net, 0, 3, 0.05, 0.0);
  net.to_space_couplings_m2 << 0.5, 0.2, 0.3, 0.0;
  net.power_W << 20.0, 0.0, 5.0, 0.0;
  const int S = 72;
  Eigen::MatrixXd loads = Eigen::MatrixXd::Zero(4, S);
  for (int k = 0; k < S; ++k)
    if (k < 46) loads(1, k) = 300.0, loads(2, k) = 40.0;
  TransientSettings settings;
  int calls = 0;
  settings.on_orbit = [&](int, double) { ++calls; };
  const PeriodicTransient tr = periodic_transient(net, loads, 5668.0, settings);
  EXPECT_LE(tr.periodicity_residual_K, 1e-3);
  EXPECT_LE(tr.orbits, 4);
  EXPECT_EQ(calls, tr.orbits);
  // Light node swings hard, heavy node barely.
  const double swing1 = tr.temperature_K.row(1).maxCoeff() - tr.temperature_K.row(1).minCoeff();
  const double swing0 = tr.temperature_K.row(0).maxCoeff() - tr.temperature_K.row(0).minCoeff();
  EXPECT_GT(swing1, 20.0);
  EXPECT_LT(swing0, swing1 / 5);
  EXPECT_LT(tr.energy.relative_imbalance(), 1e-3);
  EXPECT_LT(std::abs(tr.energy.stored_J), 1e-3 * tr.energy.absorbed_J);
}

TEST(Transient, backward_euler_is_first_order_and_crank_nicolson_second_order) {
  // One radiating node under a sinusoidal load; T(0) compared with a fine Crank-Nicolson run.
  ThermalNetwork net = network(1);
  net.capacitance_J_per_K << 2000.0;
  net.to_space_couplings_m2 << 0.5;
  auto t0 = [&](int S, double theta) {
    Eigen::MatrixXd loads(1, S);
    for (int k = 0; k < S; ++k) loads(0, k) = 200.0 + 150.0 * std::sin(2 * 3.14159265358979 * k / S);
    TransientSettings s;
    s.theta = theta;
    s.periodicity_tolerance_K = 1e-9;
    return periodic_transient(net, loads, 6000.0, s).temperature_K(0, 0);
  };
  const double ref = t0(2880, 0.5);
  const double be72 = std::abs(t0(72, 1.0) - ref), be144 = std::abs(t0(144, 1.0) - ref);
  const double cn72 = std::abs(t0(72, 0.5) - ref), cn144 = std::abs(t0(144, 0.5) - ref);
  EXPECT_NEAR(be72 / be144, 2.0, 0.2);
  EXPECT_NEAR(cn72 / cn144, 4.0, 0.4);
  EXPECT_LT(cn72, be72);
  EXPECT_THROW(t0(72, 0.2), InvalidInput);
}
