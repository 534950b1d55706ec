#pragma once
// Small thermal networks and load tables with closed-form answers, shared by the thermal tests.
#include <cmath>

#include <Eigen/Dense>

#include "thermodec/environment/loads.h"
#include "thermodec/thermal/network.h"

namespace thermodec::test {

//! One capacitive node conducting to a fixed node: C dT/dt = Q(t) - G (T - Tb), tau = C / G.
//! C [J/K], G [W/K], Tb [K]; no radiation, no power (the tests set their own).
inline ThermalNetwork single_node_to_boundary(double C, double G, double Tb) {
  ThermalNetwork net;
  net.node_names = {"node", "boundary"};
  net.capacitance_J_per_K = Eigen::Vector2d(C, 0.0);
  net.power_W = Eigen::Vector2d::Zero();
  net.fixed_temperature_K = Eigen::Vector2d(NAN, Tb);
  net.conductance_W_per_K = Eigen::Matrix2d::Zero();
  net.conductance_W_per_K(0, 1) = net.conductance_W_per_K(1, 0) = G;
  net.radiative_couplings_m2 = Eigen::Matrix2d::Zero();
  net.to_space_couplings_m2 = Eigen::Vector2d::Zero();
  return net;
}

//! S equally spaced load positions over a period P [s], every external load zero, no eclipse.
inline Loads zero_external_loads(int nodes, int S, double P) {
  Loads l;
  l.period_s = P;
  l.times_s = Eigen::VectorXd::LinSpaced(S, 0.0, P / S * (S - 1));
  l.solar_W = l.albedo_W = l.earth_ir_W = l.reflected_solar_W = Eigen::MatrixXd::Zero(nodes, S);
  l.in_shadow.assign(S, 0);
  return l;
}

}  // namespace thermodec::test
