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
#include "thermodec/environment/orbit.h"  // eclipse_switch_times_s
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
  //! N orbit-mean thermostat heater power [W] on the finest grid (duty cycle x power); empty
  //! without heaters. transient.heater_power_W: the power over the step ending at each position.
  Eigen::VectorXd heater_mean_W;
};

//! Loads (N x S at t = k P / S, with in_shadow flags) evaluated at `times_s`, each as the
//! value over the step that ends there (left limit; t = 0 as the end of the orbit):
//! albedo and Earth IR linearly interpolated; the direct-sun part from the positions that share
//! the instant's shadow state (linear, or extrapolated from two such positions next to a
//! switch), zero in shadow. With sunlit knots (Loads::knot_*, e.g. the eclipse edges) the
//! albedo and Earth IR pass through the knots too, and a sunlit instant's direct sun is linear
//! between the nearest sunlit positions or knots on either side: an arc ends on its traced
//! edges instead of an extrapolation. The shadow state of an instant: loads.in_shadow[0]
//! toggled at each of `switch_times_s` (sorted) before it.
Eigen::MatrixXd interpolated_loads_W(const Loads& loads, const Eigen::VectorXd& times_s,
                                     const Eigen::VectorXd& switch_times_s);

//! The loads as the transient applies them (interpolated_loads_W), per component, at `times_s`
//! (left limits, as there): a Loads of N x K components at those times, without knots.
Loads loads_at(const Loads& loads, const Eigen::VectorXd& times_s, const Eigen::VectorXd& switch_times_s);

//! Orbit mean of the loads as the transient applies them: the exact integral over the period of
//! interpolated_loads_W (piecewise linear between positions, switches and knots, the
//! direct sun switched at the switches) divided by P, per component, one column (time 0). The
//! sunlit share is then the exact eclipse geometry's, not the share of sunlit positions.
//! \throw InvalidInput if the loads are not S >= 2 positions over a period > 0.
Loads orbit_mean_loads(const Loads& loads, const Eigen::VectorXd& switch_times_s);

//! The loads at positions 0, 2, 4, ... (S / 2 of them, the knots kept): the coarser sampling
//! whose difference from the full one estimates the orbit sampling error (Richardson).
//! \throw InvalidInput if S is odd or < 4.
Loads every_other_position(const Loads& loads);

//! Internal power schedules (thermal/internal_power.h) are added to the loads, their switch
//! instants being step boundaries too; thermostat heaters are switched by the solver
//! (thermal/transient.h).
//! \param switch_times_s shadow entries/exits in [0, P), e.g. eclipse_switch_times_s(); empty
//! for an orbit without eclipse. They become step boundaries.
//! \throw InvalidInput if the loads are not S >= 2 positions k P / S or settings are bad;
//! SolverError from periodic_transient_on_grid.
OrbitTransient orbit_transient(const ThermalNetwork& network, const Loads& loads,
                               const Eigen::VectorXd& switch_times_s, const OrbitTimeSettings& time,
                               const TransientSettings& settings = {});

}  // namespace thermodec
