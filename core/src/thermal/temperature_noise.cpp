#include "thermodec/thermal/temperature_noise.h"

#include <algorithm>
#include <cmath>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"

namespace thermodec {

namespace {
// G_i = dQ_i/dT_i [W/K] at temperature t: radiation to everything it sees plus conduction.
double self_conductance(const ThermalNetwork& net, int i, double t) {
  double gl = 0.0, gr = net.to_space_couplings_m2[i];
  for (int j = 0; j < net.num_nodes(); ++j)
    if (j != i) {
      gl += net.conductance_W_per_K(i, j);
      gr += net.radiative_couplings_m2(i, j);
    }
  return 4.0 * kStefanBoltzmann_W_per_m2_K4 * t * t * t * gr + gl;
}
}  // namespace

Eigen::VectorXd temperature_standard_error_K(const ThermalNetwork& net, const NodeCouplings& nc,
                                            const Eigen::MatrixXd& T) {
  const int N = net.num_nodes();
  if (T.rows() != N || nc.radiative_couplings_standard_error.rows() != N ||
      nc.to_space_couplings_standard_error.size() != N)
    throw InvalidInput("temperature_standard_error_K: temperatures and couplings must have one row per node");
  Eigen::VectorXd out = Eigen::VectorXd::Zero(N);
  const double s = kStefanBoltzmann_W_per_m2_K4;
  for (int i = 0; i < N; ++i) {
    if (net.is_fixed(i)) continue;
    for (int k = 0; k < T.cols(); ++k) {
      const double ti = T(i, k), ti4 = ti * ti * ti * ti;
      double var = std::pow(s * nc.to_space_couplings_standard_error[i] * ti4, 2);
      for (int j = 0; j < N; ++j) {
        if (j == i) continue;
        const double tj = T(j, k);
        var += std::pow(s * nc.radiative_couplings_standard_error(i, j) * (tj * tj * tj * tj - ti4), 2);
      }
      const double g = self_conductance(net, i, ti);
      if (g > 0.0) out[i] = std::max(out[i], std::sqrt(var) / g);
    }
  }
  return out;
}

Eigen::VectorXd temperature_standard_error_from_loads_K(const ThermalNetwork& net, const Eigen::MatrixXd& T,
                                                       const Eigen::MatrixXd& se) {
  const int N = net.num_nodes();
  if (T.rows() != N || se.rows() != N || se.cols() != T.cols())
    throw InvalidInput("temperature_standard_error_from_loads_K: temperatures and load errors must be nodes x steps");
  Eigen::VectorXd out = Eigen::VectorXd::Zero(N);
  for (int i = 0; i < N; ++i) {
    if (net.is_fixed(i)) continue;
    for (int k = 0; k < T.cols(); ++k) {
      const double g = self_conductance(net, i, T(i, k));
      if (g > 0.0) out[i] = std::max(out[i], se(i, k) / g);
    }
  }
  return out;
}

std::vector<double> noise_targeted_sampling_boosts(const Eigen::VectorXd& sigma, double target_K, double max_boost) {
  if (!(target_K > 0.0)) throw InvalidInput("noise_targeted_sampling_boosts: target must be > 0 K");
  std::vector<double> boost(sigma.size(), 1.0);
  for (int i = 0; i < sigma.size(); ++i) {
    if (!(sigma[i] > target_K)) continue;
    const double want = std::pow(sigma[i] / target_K, 4.0 / 3.0);
    boost[i] = std::min(max_boost, std::exp2(std::ceil(std::log2(want) - 1e-9)));
  }
  return boost;
}

double noise_targeted_thinning(const Eigen::VectorXd& sigma, double target_K, double min_boost, double min_thinning) {
  if (!(target_K > 0.0)) throw InvalidInput("noise_targeted_thinning: target must be > 0 K");
  if (!(min_boost > 0.0 && min_boost <= 1.0) || !(min_thinning >= 1.0))
    throw InvalidInput("noise_targeted_thinning: min_boost must lie in (0, 1] and min_thinning be >= 1");
  double largest = 0.0;
  for (int i = 0; i < sigma.size(); ++i) {
    if (!(sigma[i] >= 0.0)) throw InvalidInput("noise_targeted_thinning: a standard error is negative or NaN");
    largest = std::max(largest, sigma[i]);
  }
  if (!(largest > 0.0) || largest >= target_K) return 1.0;
  const double f = std::exp2(std::floor(std::log2(std::pow(target_K / largest, 4.0 / 3.0)) + 1e-9));
  return f >= min_thinning ? std::max(min_boost, 1.0 / f) : 1.0;
}

}  // namespace thermodec
