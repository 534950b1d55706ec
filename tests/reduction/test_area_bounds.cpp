// Per-node area sensitivity (reduction/area_bounds.h) against closed-form steady states.
#include <gtest/gtest.h>

#include <cmath>

#include "thermodec/common/errors.h"
#include "thermodec/reduction/area_bounds.h"

namespace thermodec {
namespace {

constexpr double kSigma = 5.670374419e-8;

ThermalNetwork couplings(const Eigen::MatrixXd& gr, const Eigen::VectorXd& space) {
  ThermalNetwork c;
  const auto n = space.size();
  c.capacitance_J_per_K = Eigen::VectorXd::Zero(n);
  c.power_W = Eigen::VectorXd::Zero(n);
  c.fixed_temperature_K = Eigen::VectorXd::Constant(n, std::nan(""));
  c.conductance_W_per_K = Eigen::MatrixXd::Zero(n, n);
  c.radiative_couplings_m2 = gr;
  c.to_space_couplings_m2 = space;
  c.sink_temperature_K = 0.0;
  return c;
}

TEST(AreaBounds, NodeAloneInSpaceGetsAQuarterOfItsTemperature) {
  Eigen::MatrixXd t(1, 2);
  t << 280.0, 300.0;
  const Eigen::VectorXd s = area_sensitivity_K(couplings(Eigen::MatrixXd::Zero(1, 1), Eigen::VectorXd::Constant(1, 2.0)), t);
  EXPECT_NEAR(s[0], 300.0 / 4.0, 1e-9);  // dT = T dA / 4A at the hottest time
  const auto b = node_area_bounds(s, 0.05, 0.005);
  EXPECT_NEAR(b[0], 0.05 / 75.0, 1e-15);
  EXPECT_EQ(node_area_bounds(Eigen::VectorXd::Zero(1), 0.05, 0.005)[0], 0.005);  // insensitive: the cap
}

// Node 0 absorbs q [W] and radiates to space (GR s0) and to node 1 (GR g); node 1 only sees
// node 0 and space (GR s1). Node k's area grown by a fraction a scales its couplings by 1 + a.
struct TwoNodes {
  double q = 200.0, s0 = 0.5, s1 = 0.05, g = 0.4;
  Eigen::Vector2d solve(int grown, double a) const {
    const double f0 = grown == 0 ? 1 + a : 1.0, f1 = grown == 1 ? 1 + a : 1.0;
    const double gs0 = s0 * f0, gs1 = s1 * f1, g01 = g * f0 * f1;  // a pair coupling scales with either area
    // Node 1: T1^4 (gs1 + g01) = g01 T0^4; node 0: q = sigma (gs0 T0^4 + g01 (T0^4 - T1^4)).
    const double r = g01 / (gs1 + g01);
    const double t0_4 = q / (kSigma * (gs0 + g01 * (1 - r)));
    return {std::pow(t0_4, 0.25), std::pow(r * t0_4, 0.25)};
  }
};

TEST(AreaBounds, FirstOrderSensitivityBoundsTheSteadyStateOfTwoNodes) {
  const TwoNodes net;
  const Eigen::Vector2d t = net.solve(-1, 0.0);
  Eigen::MatrixXd gr(2, 2);
  gr << 0.0, net.g, net.g, 0.0;
  const Eigen::VectorXd s = area_sensitivity_K(couplings(gr, Eigen::Vector2d(net.s0, net.s1)), t);
  constexpr double a = 1e-4;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d moved = net.solve(k, a);
    const double worst = (moved - t).cwiseAbs().maxCoeff();
    EXPECT_NEAR(worst, a * s[k], 1e-3 * a * s[k]) << "node " << k;  // first order
  }
  // Node 1 is nearly in balance with node 0 (it sees space through a tenth of its couplings):
  // its area moves the temperatures far less than T / 4 would say.
  EXPECT_LT(s[1], 0.2 * t[1] / 4.0);
}

TEST(AreaBounds, MismatchedSizesAreRefused) {
  EXPECT_THROW(area_sensitivity_K(couplings(Eigen::MatrixXd::Zero(2, 2), Eigen::VectorXd::Zero(2)), Eigen::MatrixXd::Ones(3, 1)),
               InvalidInput);
}

}  // namespace
}  // namespace thermodec
