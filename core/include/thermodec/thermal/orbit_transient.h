#pragma once
//! Orbit-periodic temperatures converged in time, from loads ray traced at S orbit positions.
//!
//! The solver's time steps are decoupled from the load positions (as in ESATAN-TMS and Thermal
//! Desktop): loads are interpolated in time between positions, and the direct-sun part (direct
//! solar and its reflections between the spacecraft's faces) is switched at the exact eclipse
//! entry and exit instants of the orbit geometry (environment/orbit.h), which are step
//! boundaries, instead of being smeared over a position interval.
//!
//! Integrator: backward Euler (periodic_transient_on_grid, Newton per step for the T^4
//! radiation, shooting-Newton for periodicity) on grids refined by halving every step,
//! combined by Richardson extrapolation, R_L = 2 T_L - T_{L-1}: second order and L-stable
//! (both terms damp stiff modes, unlike Crank-Nicolson, which rings on the low-capacitance
//! nodes at each eclipse switch). The error of R_L is estimated by step doubling as
//! |R_L - R_{L-1}| (asymptotically 3x the error of R_L; kept whole so that the estimate stays
//! an upper bound on coarse grids), and the grid is halved until that estimate is
//! <= time_tolerance_K on every node and position.
#include <Eigen/Core>

#include "thermodec/environment/loads.h"
#include "thermodec/nodes/thermal_model.h"
#include "thermodec/thermal/network.h"
#include "thermodec/thermal/transient.h"

namespace thermodec {

struct OrbitTimeSettings {
  double time_tolerance_K = 0.01;  //!< target of the estimated time-discretization error [K]
  int substeps = 2;                //!< solver steps per load interval on the coarsest grid
  int max_levels = 7;              //!< grids tried at most (substeps x 2^0 .. 2^(max_levels-1))
};

struct OrbitTransient {
  PeriodicTransient transient;       //!< temperatures at the S load positions (extrapolated)
  double time_error_K = 0.0;         //!< estimated max |error| over nodes and positions [K]
  int solver_steps_per_orbit = 0;    //!< of the finest grid used
  Eigen::VectorXd eclipse_times_s;   //!< shadow entries and exits found in the orbit [s]
};

//! Shadow entry/exit instants [s] in [0, period_s) of the cylindrical Earth shadow
//! (orbit_state().in_shadow), located by bisection to 1e-9 of the period.
Eigen::VectorXd eclipse_switch_times_s(const Environment& environment, double period_s);

//! Loads (N x S at t = k P / S, with in_shadow flags) evaluated at `times_s`, each as the
//! value over the step that ends there (left limit; t = 0 as the end of the orbit):
//! albedo and Earth IR linearly interpolated; the direct-sun part from the positions that share
//! the instant's shadow state (linear, or extrapolated from two such positions next to a
//! switch), zero in shadow. The shadow state of an instant: loads.in_shadow[0] toggled at
//! each of `switch_times_s` (sorted) before it.
Eigen::MatrixXd interpolated_loads_W(const Loads& loads, const Eigen::VectorXd& times_s,
                                     const Eigen::VectorXd& switch_times_s);

//! \param switch_times_s shadow entries/exits in [0, P), e.g. eclipse_switch_times_s(); empty
//! for an orbit without eclipse. They become step boundaries.
//! \throw InvalidInput if the loads are not S >= 2 positions k P / S or settings are bad;
//! SolverError from periodic_transient_on_grid.
OrbitTransient orbit_transient(const ThermalNetwork& network, const Loads& loads,
                               const Eigen::VectorXd& switch_times_s, const OrbitTimeSettings& time,
                               const TransientSettings& settings = {});

}  // namespace thermodec
