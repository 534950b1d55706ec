// Per-node area bounds for a reduction's decimations (reduction/area_bounds.h).
#include "thermodec/reduction/area_bounds.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "thermodec/common/errors.h"

namespace thermodec {

Eigen::VectorXd area_sensitivity_K(const ThermalNetwork& net, const Eigen::MatrixXd& temperature_K) {
  constexpr double kSigma = 5.670374419e-8;  // [W / (m^2 K^4)]
  const Eigen::MatrixXd& gr = net.radiative_couplings_m2;
  const Eigen::VectorXd& space = net.to_space_couplings_m2;
  const Eigen::Index n = temperature_K.rows();
  const bool conduction = net.conductance_W_per_K.rows() == n && net.conductance_W_per_K.cols() == n;
  if (gr.rows() != n || gr.cols() != n || space.size() != n || net.fixed_temperature_K.size() != n)
    throw InvalidInput("area sensitivity: a network of " + std::to_string(gr.rows()) + " nodes, temperatures for " +
                       std::to_string(n));
  Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
  if (n == 0 || temperature_K.cols() == 0) return s;
  const double work = 2.0 * static_cast<double>(n) * n * n;
  const Eigen::Index stride = std::max<Eigen::Index>(1, static_cast<Eigen::Index>(std::ceil(work * temperature_K.cols() / 5e9)));
  const double sink4 = std::pow(net.sink_temperature_K, 4);
  Eigen::MatrixXd k(n, n), force(n, n);
  for (Eigen::Index t = 0; t < temperature_K.cols(); t += stride) {
    const Eigen::ArrayXd temp = temperature_K.col(t).array();
    const Eigen::ArrayXd t3 = temp.cube(), t4 = temp.square().square();
    k.setZero();
    force.setZero();  // column i: the added losses when node i's area grows by 100 % [W]
    for (Eigen::Index a = 0; a < n; ++a) {
      if (net.is_fixed(static_cast<int>(a))) {
        k(a, a) = 1.0;  // held: no change, and no losses to balance
        continue;
      }
      k(a, a) = 4.0 * kSigma * t3[a] * space[a];
      force(a, a) += kSigma * space[a] * (t4[a] - sink4);
      for (Eigen::Index b = 0; b < n; ++b) {
        if (b == a) continue;
        const double g = gr(a, b), c = conduction ? net.conductance_W_per_K(a, b) : 0.0;
        if (g == 0.0 && c == 0.0) continue;
        k(a, a) += 4.0 * kSigma * t3[a] * g + c;
        if (!net.is_fixed(static_cast<int>(b))) k(a, b) -= 4.0 * kSigma * t3[b] * g + c;
        const double exchange = kSigma * g * (t4[a] - t4[b]);  // a's loss to b [W]
        force(a, a) += exchange;  // a's couplings grow: it loses more to b
        force(a, b) += exchange;  // b's couplings grow: a loses more to b as well
      }
    }
    const Eigen::MatrixXd response = k.partialPivLu().solve(force);  // [K] per unit relative area
    for (Eigen::Index i = 0; i < n; ++i) {
      const double worst = response.col(i).cwiseAbs().maxCoeff();
      // A network without a path to a sink has no steady state: the node alone in space then.
      s[i] = std::max(s[i], std::isfinite(worst) ? worst : temp[i] / 4.0);
    }
  }
  return s;
}

std::vector<double> node_area_bounds(const Eigen::VectorXd& sensitivity_K, double budget_K, double cap) {
  std::vector<double> bound(static_cast<std::size_t>(sensitivity_K.size()), cap);
  for (Eigen::Index i = 0; i < sensitivity_K.size(); ++i)
    if (sensitivity_K[i] > 0) bound[static_cast<std::size_t>(i)] = std::min(cap, budget_K / sensitivity_K[i]);
  return bound;
}

}  // namespace thermodec
