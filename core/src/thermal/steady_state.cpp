#include "thermodec/thermal/steady_state.h"

#include <Eigen/LU>
#include <cmath>

#include "heat_balance.h"
#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"

namespace thermodec {
namespace detail {

// Starting point for Newton: the network with radiation linearised at 290 K (h = 4 sigma T^3).
// T^4 makes Newton overshoot badly from a poor guess; this one is within tens of kelvin for
// spacecraft-like networks and costs one small linear solve.
Eigen::VectorXd linearised_guess(const HeatBalance& hb, const Eigen::VectorXd& external_W) {
  const int m = static_cast<int>(hb.free_nodes.size());
  const double t_ref = 290.0;
  const double h = 4.0 * kStefanBoltzmann_W_per_m2_K4 * t_ref * t_ref * t_ref;
  const double q4 = 3.0 * kStefanBoltzmann_W_per_m2_K4 * std::pow(t_ref, 4);  // sigma T^4 ~ h T - 3 sigma T_ref^4
  const Eigen::MatrixXd K = hb.GL + h * hb.GR;
  Eigen::MatrixXd A(m, m);
  Eigen::VectorXd b(m);
  for (int a = 0; a < m; ++a) {
    const int i = hb.free_nodes[a];
    b[a] = hb.net.power_W[i] + external_W[i] + hb.net.to_space_couplings_m2[i] * (kStefanBoltzmann_W_per_m2_K4 * hb.sink4 + q4);
    A(a, a) = hb.GL_row[i] + h * (hb.GR_row[i] + hb.net.to_space_couplings_m2[i]);
    for (int c = 0; c < m; ++c)
      if (c != a) A(a, c) = -K(i, hb.free_nodes[c]);
    for (int j : hb.fixed_nodes) b[a] += K(i, j) * hb.net.fixed_temperature_K[j];
  }
  Eigen::VectorXd x = Eigen::PartialPivLU<Eigen::MatrixXd>(A).solve(b);
  for (int a = 0; a < m; ++a)
    if (!std::isfinite(x[a]) || x[a] < 20.0 || x[a] > 3000.0) x[a] = std::isfinite(x[a]) && x[a] > 3000.0 ? 3000.0 : 20.0;
  return x;
}

std::vector<std::string> free_names(const HeatBalance& hb) {
  std::vector<std::string> names;
  for (int i : hb.free_nodes) names.push_back(hb.net.node_names[i]);
  return names;
}

}  // namespace detail

SteadyState steady_state(const ThermalNetwork& network, const Eigen::VectorXd& external_W,
                         const NewtonSettings& settings) {
  validate_network(network);
  detail::validate_loads(network, external_W, "steady state");
  detail::require_paths_to_sinks(network, "steady state");
  const detail::HeatBalance hb(network);
  Eigen::VectorXd x = detail::linearised_guess(hb, external_W);
  SteadyState out;
  out.iterations = detail::newton_solve(
      x,
      [&](const Eigen::VectorXd& xf, Eigen::VectorXd& G, Eigen::MatrixXd* J) {
        const Eigen::VectorXd T = hb.full(xf);
        G = hb.restrict(hb.residual(T, external_W));
        if (J) *J = hb.restrict(hb.jacobian(T));
      },
      settings, "steady state", detail::free_names(hb), &out.max_residual_W);
  out.temperature_K = hb.full(x);
  return out;
}

}  // namespace thermodec
