#include "heat_balance.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <queue>
#include <sstream>

#include "thermodec/common/errors.h"
#include "thermodec/environment/orbit.h"

namespace thermodec::detail {
namespace {
constexpr double kSigma = kStefanBoltzmann_W_per_m2_K4;
}

HeatBalance::HeatBalance(const ThermalNetwork& network) : net(network) {
  GL = network.conductance_W_per_K;
  GR = network.radiative_couplings_m2;
  GL.diagonal().setZero();
  GR.diagonal().setZero();
  GL_row = GL.rowwise().sum();
  GR_row = GR.rowwise().sum();
  for (int i = 0; i < network.num_nodes(); ++i)
    (network.is_fixed(i) ? fixed_nodes : free_nodes).push_back(i);
  sink4 = std::pow(network.sink_temperature_K, 4);
}

Eigen::VectorXd HeatBalance::residual(const Eigen::VectorXd& T, const Eigen::VectorXd& E) const {
  const Eigen::VectorXd T4 = T.array().pow(4).matrix();
  Eigen::VectorXd r = net.power_W + E;
  r += GL * T - GL_row.cwiseProduct(T);
  r += kSigma * (GR * T4 - GR_row.cwiseProduct(T4));
  r += kSigma * net.to_space_couplings_m2.cwiseProduct((Eigen::VectorXd::Constant(T.size(), sink4) - T4));
  return r;
}

Eigen::MatrixXd HeatBalance::jacobian(const Eigen::VectorXd& T) const {
  const Eigen::VectorXd T3 = T.array().pow(3).matrix();
  Eigen::MatrixXd J = GL + 4.0 * kSigma * GR * T3.asDiagonal();
  J.diagonal() -= GL_row + 4.0 * kSigma * T3.cwiseProduct(GR_row + net.to_space_couplings_m2);
  return J;
}

Eigen::VectorXd HeatBalance::to_space_W(const Eigen::VectorXd& T) const {
  const Eigen::VectorXd T4 = T.array().pow(4).matrix();
  return kSigma * net.to_space_couplings_m2.cwiseProduct(T4 - Eigen::VectorXd::Constant(T.size(), sink4));
}

Eigen::VectorXd HeatBalance::to_fixed_W(const Eigen::VectorXd& T) const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(T.size());
  for (int i : free_nodes)
    for (int j : fixed_nodes)
      q[i] += GL(i, j) * (T[i] - T[j]) + kSigma * GR(i, j) * (std::pow(T[i], 4) - std::pow(T[j], 4));
  return q;
}

Eigen::VectorXd HeatBalance::full(const Eigen::VectorXd& x) const {
  Eigen::VectorXd T = net.fixed_temperature_K;
  for (size_t k = 0; k < free_nodes.size(); ++k) T[free_nodes[k]] = x[k];
  return T;
}

Eigen::VectorXd HeatBalance::restrict(const Eigen::VectorXd& v) const {
  Eigen::VectorXd x(free_nodes.size());
  for (size_t k = 0; k < free_nodes.size(); ++k) x[k] = v[free_nodes[k]];
  return x;
}

Eigen::MatrixXd HeatBalance::restrict(const Eigen::MatrixXd& m) const {
  const int n = static_cast<int>(free_nodes.size());
  Eigen::MatrixXd out(n, n);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) out(a, b) = m(free_nodes[a], free_nodes[b]);
  return out;
}

void require_paths_to_sinks(const ThermalNetwork& network, const std::string& what) {
  const auto stranded = nodes_without_path_to_sink(network);
  if (stranded.empty()) return;
  std::string list;
  for (size_t k = 0; k < stranded.size() && k < 20; ++k) list += (k ? ", " : "") + stranded[k];
  if (stranded.size() > 20) list += ", ... (" + std::to_string(stranded.size()) + " in all)";
  throw SolverError(what + ": node(s) with no conductive or radiative path to a heat sink "
                    "(deep space or a fixed-temperature node), temperature undetermined: " + list);
}

int newton_solve(Eigen::VectorXd& x,
                 const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&, Eigen::MatrixXd*)>& evaluate,
                 const NewtonSettings& s, const std::string& what, const std::vector<std::string>& names,
                 double* final_residual) {
  if (x.size() == 0) return 0;
  Eigen::VectorXd G, G_trial;
  Eigen::MatrixXd J;
  evaluate(x, G, &J);
  for (int it = 1; it <= s.max_iterations; ++it) {
    const double norm0 = G.norm();
    if (G.cwiseAbs().maxCoeff() <= s.residual_tolerance_W) {
      if (final_residual) *final_residual = G.cwiseAbs().maxCoeff();
      return it - 1;
    }
    const Eigen::VectorXd step = -Eigen::PartialPivLU<Eigen::MatrixXd>(J).solve(G);
    if (!step.allFinite())
      throw SolverError(what + ": singular Jacobian (a node is decoupled from every sink)");
    // Backtracking: halve until the residual norm decreases and temperatures stay positive.
    double alpha = 1.0;
    Eigen::VectorXd x_trial;
    bool accepted = false;
    for (int ls = 0; ls < 40; ++ls, alpha *= 0.5) {
      x_trial = x + alpha * step;
      if ((x_trial.array() <= 0.0).any()) continue;
      evaluate(x_trial, G_trial, nullptr);
      if (G_trial.allFinite() && G_trial.norm() <= (1.0 - 1e-4 * alpha) * norm0) {
        accepted = true;
        break;
      }
    }
    const double moved = (alpha * step).cwiseAbs().maxCoeff();
    if (!accepted) {
      // A small step that cannot reduce the residual further: at round-off level
      // (NewtonSettings::stalled_step_K).
      if (step.cwiseAbs().maxCoeff() <= std::max(s.stalled_step_K, s.temperature_tolerance_K * 10)) {
        if (final_residual) *final_residual = G.cwiseAbs().maxCoeff();
        return it;
      }
      Eigen::Index worst = 0;
      G.cwiseAbs().maxCoeff(&worst);
      std::ostringstream msg;
      msg << what << ": Newton line search failed at iteration " << it << ", max heat-balance residual "
          << G.cwiseAbs().maxCoeff() << " W at node '" << names[worst] << "' (Newton step "
          << step.cwiseAbs().maxCoeff() << " K)";
      throw SolverError(msg.str());
    }
    x = x_trial;
    evaluate(x, G, &J);
    if (moved <= s.temperature_tolerance_K) {
      if (final_residual) *final_residual = G.cwiseAbs().maxCoeff();
      return it;
    }
  }
  Eigen::Index worst = 0;
  G.cwiseAbs().maxCoeff(&worst);
  std::ostringstream msg;
  msg << what << ": Newton did not converge in " << s.max_iterations << " iterations, max heat-balance residual "
      << G.cwiseAbs().maxCoeff() << " W at node '" << names[worst] << "'";
  throw SolverError(msg.str());
}

void validate_loads(const ThermalNetwork& network, const Eigen::MatrixXd& loads, const char* what) {
  if (loads.rows() != network.num_nodes())
    throw InvalidInput(std::string(what) + ": " + std::to_string(loads.rows()) + " load rows for " +
                       std::to_string(network.num_nodes()) + " nodes");
  if (!loads.allFinite()) throw InvalidInput(std::string(what) + ": loads are not finite");
}

}  // namespace thermodec::detail

namespace thermodec {

std::vector<std::string> nodes_without_path_to_sink(const ThermalNetwork& net) {
  const int n = net.num_nodes();
  std::vector<char> reached(n, 0);
  std::queue<int> q;
  for (int i = 0; i < n; ++i)
    if (net.is_fixed(i) || net.to_space_couplings_m2[i] > 0.0) {
      reached[i] = 1;
      q.push(i);
    }
  while (!q.empty()) {
    const int i = q.front();
    q.pop();
    for (int j = 0; j < n; ++j)
      if (!reached[j] && j != i &&
          (net.conductance_W_per_K(i, j) > 0.0 || net.radiative_couplings_m2(i, j) > 0.0)) {
        reached[j] = 1;
        q.push(j);
      }
  }
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i)
    if (!reached[i]) out.push_back(net.node_names[i]);
  return out;
}

}  // namespace thermodec
