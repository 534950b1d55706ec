// Time-varying internal power: a piecewise-constant schedule over the orbit against the
// closed-form periodic solution, and a thermostat heater holding its node within its band.
#include <gtest/gtest.h>

#include <cmath>

#include "thermodec/common/errors.h"
#include "thermodec/thermal/internal_power.h"
#include "thermodec/thermal/orbit_transient.h"
#include "common/small_networks.h"

using namespace thermodec;
using test::single_node_to_boundary;
using test::zero_external_loads;

TEST(PowerSchedule, square_wave_matches_the_closed_form_periodic_solution) {
  // Q = Q1 on [0, L1), 0 on [L1, P); the switch at 2000 s falls inside a load interval (250 s).
  const double C = 3000.0, G = 1.0, Tb = 280.0, P = 6000.0, Q1 = 20.0, L1 = 2000.0, tau = C / G;
  ThermalNetwork net = single_node_to_boundary(C, G, Tb);
  net.power_schedule_W = {{{0.0, Q1}, {L1, 0.0}}, {}};
  const int S = 24;
  OrbitTimeSettings time;
  time.time_tolerance_K = 0.005;
  const OrbitTransient ot = orbit_transient(net, zero_external_loads(2, S, P), Eigen::VectorXd(), time);
  // Periodic solution: T_min at 0, T_max at L1, exponential approach to T1 / T0 in between.
  const double T1 = Tb + Q1 / G, T0 = Tb, a1 = std::exp(-L1 / tau), a0 = std::exp(-(P - L1) / tau);
  const double T_min = (T0 * (1 - a0) + T1 * (1 - a1) * a0) / (1 - a0 * a1);
  const double T_max = T1 + (T_min - T1) * a1;
  for (int k = 0; k < S; ++k) {
    const double t = k * P / S;
    const double exact = t <= L1 ? T1 + (T_min - T1) * std::exp(-t / tau) : T0 + (T_max - T0) * std::exp(-(t - L1) / tau);
    // time_error_K bounds the error of the extrapolated temperatures (orbit_transient.h).
    EXPECT_NEAR(ot.transient.temperature_K(0, k), exact, ot.time_error_K + 1e-9) << "t = " << t;
  }
  EXPECT_LE(ot.time_error_K, time.time_tolerance_K);
  EXPECT_GT(T_max - T_min, 5.0);  // the schedule shows: a 6.7 K swing
  EXPECT_NEAR(scheduled_power_mean_W(net, P)[0], Q1 * L1 / P, 1e-12);
}

TEST(PowerSchedule, times_outside_the_orbit_are_refused) {
  ThermalNetwork net = single_node_to_boundary(3000.0, 1.0, 280.0);
  net.power_schedule_W = {{{0.0, 5.0}, {7000.0, 0.0}}, {}};
  EXPECT_THROW(orbit_transient(net, zero_external_loads(2, 8, 6000.0), Eigen::VectorXd(), {}), InvalidInput);
}

TEST(Thermostat, heater_holds_its_node_within_its_band_through_the_cold_half) {
  // 150 W over the first half orbit, none over the second (an eclipse), a sink at 200 K:
  // without a heater the node swings 240-310 K. A 90 W heater switched on below 270 K and off
  // above 275 K (90 W alone would reach 290 K) comes on ~1360 s into the cold half and cycles
  // the node within the band to the end of the orbit; the sun switches it off again.
  const double C = 3000.0, G = 1.0, Tb = 200.0, P = 6000.0;
  ThermalNetwork net = single_node_to_boundary(C, G, Tb);
  net.power_schedule_W = {{{0.0, 150.0}, {P / 2, 0.0}}, {}};
  const int S = 24;
  OrbitTimeSettings time;
  time.time_tolerance_K = 0.01;
  TransientSettings settings;
  settings.max_orbits = 30;
  const OrbitTransient free_run = orbit_transient(net, zero_external_loads(2, S, P), Eigen::VectorXd(), time, settings);
  EXPECT_LT(free_run.transient.temperature_K.row(0).minCoeff(), 250.0);
  net.heaters.push_back({0, Thermostat{270.0, 275.0, 90.0}});
  const OrbitTransient ot = orbit_transient(net, zero_external_loads(2, S, P), Eigen::VectorXd(), time, settings);
  // A switch is located within its step by linear interpolation; allow the whole step, at the
  // fastest rate in the band (cooling towards 200 K from 275 K: 75 K / tau), for the coarser
  // grid of the extrapolated pair (twice the finest step); plus the estimated time error.
  const double step_s = P / ot.solver_steps_per_orbit, rate = 75.0 / (C / G);
  const double slack = rate * 2.0 * step_s + ot.time_error_K;
  for (int k = 18; k <= S; ++k) {  // 4500 s .. the end of the orbit (= position 0)
    const double T = ot.transient.temperature_K(0, k % S);
    EXPECT_GE(T, 270.0 - slack) << "position " << k;
    EXPECT_LE(T, 275.0 + slack) << "position " << k;
  }
  EXPECT_GE(ot.transient.temperature_K.row(0).minCoeff(), 270.0 - slack);
  ASSERT_EQ(ot.heater_mean_W.size(), 2);
  EXPECT_GT(ot.heater_mean_W[0], 0.0);
  EXPECT_LT(ot.heater_mean_W[0], 90.0 * 0.5);  // on part of the cold half only
  EXPECT_LE(ot.transient.energy.relative_imbalance(), 1e-6);
}

TEST(Thermostat, needs_a_free_node_with_capacitance) {
  ThermalNetwork net = single_node_to_boundary(3000.0, 1.0, 200.0);
  net.heaters.push_back({1, Thermostat{270.0, 275.0, 90.0}});  // the fixed node
  EXPECT_THROW(validate_network(net), InvalidInput);
  net.heaters = {{0, Thermostat{275.0, 270.0, 90.0}}};  // band upside down
  EXPECT_THROW(validate_network(net), InvalidInput);
}
