#pragma once
//! Steady-state temperatures of a thermal network (thermal/network.h) by Newton's method with
//! a backtracking line search on the heat-balance residual.
#include <Eigen/Core>

#include "thermodec/thermal/network.h"

namespace thermodec {

//! Newton settings shared by the steady and the transient solvers.
struct NewtonSettings {
  double temperature_tolerance_K = 1e-9;  //!< converged when the last step moves no node more
  double residual_tolerance_W = 1e-9;     //!< ... or every node's heat balance is within this
  //! A Newton step the line search cannot use (the residual no longer decreases: its round-off
  //! on nodes exchanging hundreds of watts) ends the solve when it moves no node more than
  //! this [K]: the temperatures are then exact to it, far below the Monte Carlo noise (~1e-3 K).
  double stalled_step_K = 1e-6;
  int max_iterations = 100;
};

struct SteadyState {
  Eigen::VectorXd temperature_K;  //!< N, fixed nodes at their boundary temperature
  int iterations = 0;
  double max_residual_W = 0.0;    //!< largest |heat balance| at the solution
};

//! Solves 0 = Q + E + conduction + radiation for the free nodes.
//! \param external_loads_W N absorbed external powers E [W].
//! \throw SolverError listing the nodes with no path to a sink, or if Newton stalls (with the
//! residual and the worst node).
//! \throw InvalidInput on malformed network or loads of the wrong size / not finite.
SteadyState steady_state(const ThermalNetwork& network, const Eigen::VectorXd& external_loads_W,
                         const NewtonSettings& settings = {});

}  // namespace thermodec
