#pragma once
// Internal: heat-balance residual and Jacobian of a thermal network and the damped Newton
// iteration shared by the steady and transient solvers.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "thermodec/thermal/network.h"
#include "thermodec/thermal/steady_state.h"

namespace thermodec::detail {

//! Dense network matrices with zeroed diagonals and cached row sums.
struct HeatBalance {
  explicit HeatBalance(const ThermalNetwork& network);

  //! Net heat into each node [W] at full temperature vector T (N): P + E + GL + GR + space.
  Eigen::VectorXd residual(const Eigen::VectorXd& T, const Eigen::VectorXd& external_W) const;
  //! dR/dT (N x N).
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& T) const;
  //! Per node: heat radiated to deep space [W] (net of the sink), sigma GRs (T^4 - Ts^4).
  Eigen::VectorXd to_space_W(const Eigen::VectorXd& T) const;
  //! Per free node: heat flowing into fixed nodes [W].
  Eigen::VectorXd to_fixed_W(const Eigen::VectorXd& T) const;

  const ThermalNetwork& net;
  Eigen::MatrixXd GL, GR;       // zero diagonal
  Eigen::VectorXd GL_row, GR_row;
  std::vector<int> free_nodes;  // indices of free nodes
  std::vector<int> fixed_nodes;
  double sink4 = 0.0;

  Eigen::VectorXd full(const Eigen::VectorXd& x_free) const;        // free -> N with fixed values
  Eigen::VectorXd restrict(const Eigen::VectorXd& v_full) const;     // N -> free entries
  Eigen::MatrixXd restrict(const Eigen::MatrixXd& m_full) const;     // free x free block
};

//! Throws SolverError listing nodes without a path to a sink (what = "steady state" ...).
void require_paths_to_sinks(const ThermalNetwork& network, const std::string& what);

//! Damped Newton on G(x) = 0 with x > 0. `evaluate(x, G, J)` fills the residual and Jacobian.
//! Returns iterations used. \throw SolverError (message starts with `what`) on failure.
int newton_solve(Eigen::VectorXd& x,
                 const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&, Eigen::MatrixXd*)>& evaluate,
                 const NewtonSettings& settings, const std::string& what,
                 const std::vector<std::string>& names, double* final_residual = nullptr);

void validate_loads(const ThermalNetwork& network, const Eigen::MatrixXd& loads_W, const char* what);

}  // namespace thermodec::detail
