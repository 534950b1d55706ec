#include "thermodec/thermal/temperature_noise.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <vector>

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

namespace {

// Variance [K^2] of each free node's temperature at one step (temperatures t), the sources
// propagated through the inverse Jacobian of the free nodes' heat balance.
Eigen::VectorXd step_variance_K2(const ThermalNetwork& net, const NodeCouplings& nc, const Eigen::VectorXd& t,
                                 const Eigen::VectorXd* load_se) {
  const int N = net.num_nodes();
  const double s = kStefanBoltzmann_W_per_m2_K4;
  std::vector<int> free_of(N, -1), nodes;
  for (int i = 0; i < N; ++i)
    if (!net.is_fixed(i)) free_of[i] = static_cast<int>(nodes.size()), nodes.push_back(i);
  const int F = static_cast<int>(nodes.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(F, F);
  for (int a = 0; a < F; ++a) {
    const int i = nodes[a];
    K(a, a) = self_conductance(net, i, t[i]);
    for (int b = 0; b < F; ++b)
      if (b != a) {
        const int j = nodes[b];
        K(a, b) = -(net.conductance_W_per_K(i, j) + 4.0 * s * net.radiative_couplings_m2(i, j) * t[j] * t[j] * t[j]);
      }
  }
  Eigen::VectorXd var = Eigen::VectorXd::Zero(N);
  if (F == 0) return var;
  const Eigen::MatrixXd Kinv = K.partialPivLu().inverse();
  Eigen::VectorXd v(F);
  for (int a = 0; a < F; ++a) {
    const int i = nodes[a];
    const double ti4 = std::pow(t[i], 4);
    double q = load_se ? (*load_se)[i] : 0.0;
    // Sources into node i alone: its loads and its coupling to space, independent.
    for (const double src : {q, s * nc.to_space_couplings_standard_error[i] * ti4}) {
      if (src == 0.0) continue;
      for (int b = 0; b < F; ++b) var[nodes[b]] += std::pow(Kinv(b, a) * src, 2);
    }
    // A coupling to node j: its error moves heat from one node to the other (one source per pair).
    for (int j = 0; j < N; ++j) {
      if (j == i || (free_of[j] >= 0 && free_of[j] < a)) continue;
      const double se = 0.5 * (nc.radiative_couplings_standard_error(i, j) + nc.radiative_couplings_standard_error(j, i));
      const double dq = s * se * (std::pow(t[j], 4) - ti4);
      if (dq == 0.0) continue;
      const int c = free_of[j];
      for (int b = 0; b < F; ++b) var[nodes[b]] += std::pow((Kinv(b, a) - (c >= 0 ? Kinv(b, c) : 0.0)) * dq, 2);
    }
  }
  return var;
}

}  // namespace

Eigen::VectorXd temperature_noise_K(const ThermalNetwork& net, const NodeCouplings& nc, const Eigen::MatrixXd& T,
                                    const Eigen::MatrixXd& load_se) {
  const int N = net.num_nodes();
  if (T.rows() != N || nc.radiative_couplings_standard_error.rows() != N ||
      nc.radiative_couplings_standard_error.cols() != N || nc.to_space_couplings_standard_error.size() != N)
    throw InvalidInput("temperature_noise_K: temperatures and couplings must have one row per node");
  const bool loads = load_se.size() > 0;
  if (loads && (load_se.rows() != N || load_se.cols() != T.cols()))
    throw InvalidInput("temperature_noise_K: load errors must be nodes x steps like the temperatures");
  // Cost N^3 per step evaluated: large networks take every stride-th step and the hottest.
  const double per_step = std::pow(double(N), 3);
  const int stride = std::max<int>(1, static_cast<int>(std::ceil(per_step * T.cols() / 4e9)));
  std::vector<int> steps;
  for (int k = 0; k < T.cols(); k += stride) steps.push_back(k);
  if (stride > 1 && T.size() > 0) {
    Eigen::Index r = 0, c = 0;
    T.maxCoeff(&r, &c);
    steps.push_back(static_cast<int>(c));
  }
  Eigen::VectorXd worst = Eigen::VectorXd::Zero(N);
  for (const int k : steps) {
    const Eigen::VectorXd se_k = loads ? Eigen::VectorXd(load_se.col(k)) : Eigen::VectorXd();
    worst = worst.cwiseMax(step_variance_K2(net, nc, T.col(k), loads ? &se_k : nullptr));
  }
  return worst.cwiseSqrt();
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
