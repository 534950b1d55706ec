// Noise-targeted sampling: the temperature noise estimate and the boosts it asks for.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"
#include "thermodec/thermal/steady_state.h"
#include "thermodec/thermal/temperature_noise.h"

using namespace thermodec;

namespace {
ThermalNetwork one_node_to_space(double gr_space_m2) {
  ThermalNetwork net;
  net.node_names = {"plate"};
  net.capacitance_J_per_K = Eigen::VectorXd::Zero(1);
  net.power_W = Eigen::VectorXd::Zero(1);
  net.fixed_temperature_K = Eigen::VectorXd::Constant(1, std::numeric_limits<double>::quiet_NaN());
  net.conductance_W_per_K = Eigen::MatrixXd::Zero(1, 1);
  net.radiative_couplings_m2 = Eigen::MatrixXd::Zero(1, 1);
  net.to_space_couplings_m2 = Eigen::VectorXd::Constant(1, gr_space_m2);
  return net;
}
}  // namespace

TEST(TemperatureNoise, node_radiating_to_space_matches_the_linearised_balance) {
  // Q = sigma GR T^4 fixed: dT/T = -dGR / (4 GR), so sigma_T = SE(GR) T / (4 GR).
  const ThermalNetwork net = one_node_to_space(2.0);
  NodeCouplings nc;
  nc.radiative_couplings_standard_error = Eigen::MatrixXd::Zero(1, 1);
  nc.to_space_couplings_standard_error = Eigen::VectorXd::Constant(1, 0.01);
  Eigen::MatrixXd T(1, 3);
  T << 250.0, 300.0, 280.0;  // the largest over the steps
  const Eigen::VectorXd s = temperature_standard_error_K(net, nc, T);
  EXPECT_NEAR(s[0], 0.01 * 300.0 / (4.0 * 2.0), 1e-12);
  // a load error dQ moves T by dQ / (4 sigma T^3 GR)
  const Eigen::MatrixXd dQ = Eigen::MatrixXd::Constant(1, 3, 0.5);
  const Eigen::VectorXd l = temperature_standard_error_from_loads_K(net, T, dQ);
  EXPECT_NEAR(l[0], 0.5 / (4.0 * kStefanBoltzmann_W_per_m2_K4 * std::pow(250.0, 3) * 2.0), 1e-12);
  EXPECT_THROW(temperature_standard_error_from_loads_K(net, T, Eigen::MatrixXd::Zero(1, 2)), InvalidInput);
}

TEST(TemperatureNoise, node_between_two_others_weighs_each_coupling_by_the_T4_difference) {
  // Node 0 couples to a hot (1) and a cold (2) node; only GR_01 is uncertain.
  ThermalNetwork net = one_node_to_space(0.0);
  net.node_names = {"a", "hot", "cold"};
  net.capacitance_J_per_K = Eigen::VectorXd::Zero(3);
  net.power_W = Eigen::VectorXd::Zero(3);
  net.fixed_temperature_K = Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 350.0, 200.0);
  net.conductance_W_per_K = Eigen::MatrixXd::Zero(3, 3);
  net.radiative_couplings_m2 = Eigen::MatrixXd::Zero(3, 3);
  net.radiative_couplings_m2(0, 1) = net.radiative_couplings_m2(1, 0) = 1.0;
  net.radiative_couplings_m2(0, 2) = net.radiative_couplings_m2(2, 0) = 1.0;
  net.to_space_couplings_m2 = Eigen::VectorXd::Zero(3);
  NodeCouplings nc;
  nc.radiative_couplings_standard_error = Eigen::MatrixXd::Zero(3, 3);
  nc.radiative_couplings_standard_error(0, 1) = nc.radiative_couplings_standard_error(1, 0) = 0.002;
  nc.to_space_couplings_standard_error = Eigen::VectorXd::Zero(3);
  const Eigen::MatrixXd T = Eigen::Vector3d(300.0, 350.0, 200.0);
  const Eigen::VectorXd s = temperature_standard_error_K(net, nc, T);
  const double sb = kStefanBoltzmann_W_per_m2_K4;
  const double expect = sb * 0.002 * (std::pow(350.0, 4) - std::pow(300.0, 4)) / (4.0 * sb * std::pow(300.0, 3) * 2.0);
  EXPECT_NEAR(s[0], expect, 1e-12);
  EXPECT_EQ(s[1], 0.0);  // fixed nodes carry no noise
  EXPECT_THROW(temperature_standard_error_K(net, nc, Eigen::MatrixXd::Zero(2, 1)), InvalidInput);
}

TEST(TemperatureNoise, boosts_are_powers_of_two_that_reach_the_target_within_the_cap) {
  Eigen::VectorXd s(4);
  s << 0.005, 0.02, 0.05, 10.0;
  const std::vector<double> b = noise_targeted_sampling_boosts(s, 0.01, 64.0);
  // (sigma / target)^(4/3): 2^(4/3) = 2.5 -> 4, 5^(4/3) = 8.5 -> 16, 1000^(4/3) -> cap 64
  EXPECT_EQ(b, (std::vector<double>{1.0, 4.0, 16.0, 64.0}));
  EXPECT_THROW(noise_targeted_sampling_boosts(s, 0.0), InvalidInput);
  EXPECT_THROW(noise_targeted_sampling_boosts(s, std::nan("")), InvalidInput);
}

TEST(TemperatureNoise, an_oversampled_model_is_thinned_by_one_power_of_two_that_keeps_every_node_under_target) {
  Eigen::VectorXd s(3);
  s << 0.001, 0.002, 0.0;  // the noisiest node sets the factor; a noiseless (fixed) node none
  // (0.01 / 0.002)^(4/3) = 8.55 -> 8: every node's error x 8^(3/4) = 4.76 stays under target
  EXPECT_EQ(noise_targeted_thinning(s, 0.01), 1.0 / 8.0);
  EXPECT_LE(0.002 * std::pow(8.0, 0.75), 0.01);
  EXPECT_EQ(noise_targeted_thinning(s, 0.01, 1.0 / 4.0), 1.0 / 4.0);  // at most min_boost
  EXPECT_EQ(noise_targeted_thinning(s, 0.1), 1.0 / 64.0);             // 470x of room: the floor
  EXPECT_EQ(noise_targeted_thinning(s, 0.004), 1.0);                  // room 2.5 -> 2 < 4: kept
  EXPECT_EQ(noise_targeted_thinning(s, 0.004, 1.0 / 64.0, 2.0), 0.5);
  EXPECT_EQ(noise_targeted_thinning(s, 0.0015), 1.0);                 // a node above target
  EXPECT_EQ(noise_targeted_thinning(Eigen::VectorXd::Zero(2), 0.01), 1.0);  // nothing to go by
  EXPECT_EQ(noise_targeted_thinning(s, 0.01, 1.0), 1.0);              // min_boost 1: never
  EXPECT_THROW(noise_targeted_thinning(s, 0.0), InvalidInput);
  EXPECT_THROW(noise_targeted_thinning(s, 0.01, 0.0), InvalidInput);
  s[2] = std::nan("");
  EXPECT_THROW(noise_targeted_thinning(s, 0.01), InvalidInput);
}

TEST(TemperatureNoise, network_propagation_matches_steady_solves_with_each_error_applied) {
  // Three free nodes in a chain (conduction and radiation) and to space; a load error on node
  // 0 and a coupling error on GR_12. Each error applied alone to the steady balance moves the
  // temperatures by K^-1 dQ to first order: the noise is the quadrature sum of those moves, and
  // the node-by-node estimate misses node 2's share of node 0's load error entirely.
  ThermalNetwork net = one_node_to_space(0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  net.node_names = {"a", "b", "c"};
  net.capacitance_J_per_K = Eigen::VectorXd::Constant(3, 1000.0);
  net.power_W = Eigen::Vector3d(200.0, 50.0, 10.0);
  net.fixed_temperature_K = Eigen::Vector3d(nan, nan, nan);
  net.conductance_W_per_K = Eigen::MatrixXd::Zero(3, 3);
  net.conductance_W_per_K(0, 1) = net.conductance_W_per_K(1, 0) = 2.0;
  net.radiative_couplings_m2 = Eigen::MatrixXd::Zero(3, 3);
  net.radiative_couplings_m2(1, 2) = net.radiative_couplings_m2(2, 1) = 0.5;
  net.to_space_couplings_m2 = Eigen::Vector3d(0.3, 0.4, 0.6);
  NodeCouplings nc;
  nc.radiative_couplings_standard_error = Eigen::MatrixXd::Zero(3, 3);
  nc.radiative_couplings_standard_error(1, 2) = nc.radiative_couplings_standard_error(2, 1) = 0.005;
  nc.to_space_couplings_standard_error = Eigen::VectorXd::Zero(3);
  const Eigen::Vector3d dq0(1.0, 0.0, 0.0);  // load standard error [W]
  const Eigen::VectorXd T = steady_state(net, Eigen::VectorXd::Zero(3)).temperature_K;
  const Eigen::VectorXd noise = temperature_noise_K(net, nc, T, Eigen::MatrixXd(dq0));
  // Finite differences: each error applied alone (+1 sigma), solved again.
  const Eigen::VectorXd by_load = steady_state(net, dq0).temperature_K - T;
  ThermalNetwork moved = net;
  moved.radiative_couplings_m2(1, 2) = moved.radiative_couplings_m2(2, 1) = 0.505;
  const Eigen::VectorXd by_coupling = steady_state(moved, Eigen::VectorXd::Zero(3)).temperature_K - T;
  for (int i = 0; i < 3; ++i) {
    const double expected = std::hypot(by_load[i], by_coupling[i]);
    EXPECT_NEAR(noise[i], expected, 0.02 * expected) << net.node_names[i];
  }
  EXPECT_GT(noise[2], 0.0);
  EXPECT_EQ(temperature_standard_error_from_loads_K(net, Eigen::MatrixXd(T), Eigen::MatrixXd(dq0))[2], 0.0);
}
