#pragma once
//! Orbit-periodic transient of a thermal network (thermal/network.h) under periodic loads.
//!
//! Time stepping: theta method on S equal steps of one period, Newton with line search per
//! step (theta = 1: backward Euler, the default; arithmetic nodes always use theta = 1).
//! Periodicity: shooting. Each orbit also propagates the sensitivity M = dT(P)/dT(0); the
//! next orbit starts from the Newton update of T(0) - T(P) = 0, i.e.
//! T0 += (I - M)^-1 (T(P) - T0). Converged when max_i |T_i(P) - T_i(0)| <= tolerance; the
//! first orbit starts from the steady state of the orbit-averaged loads.
//!
//! Thermostat heaters (ThermalNetwork::heaters): switched at the start of each step by their
//! node's temperature there and held over the step, so a switch comes up to one step late (the
//! orbit transient's step-doubling error estimate includes that). Their on/off states are part
//! of the periodic state: an orbit is periodic only if every heater ends it as it began. A
//! switch pins its node's temperature (to the band edge) whatever the start, so the shooting
//! sensitivity of that node is reset there. A heater that cycles out of step with the orbit
//! has no orbit-periodic state: the run then ends with the not-periodic error.
#include <Eigen/Core>
#include <functional>

#include "thermodec/thermal/network.h"
#include "thermodec/thermal/steady_state.h"

namespace thermodec {

struct TransientSettings {
  double periodicity_tolerance_K = 1e-3;  //!< max |T(P) - T(0)| over nodes at convergence
  int max_orbits = 10;                    //!< orbits simulated at most
  double theta = 1.0;                     //!< 1 = backward Euler, 0.5 = Crank-Nicolson
  NewtonSettings newton;
  //! Optional: called after each orbit with (orbit number from 1, periodicity residual [K]).
  std::function<void(int, double)> on_orbit;
};

//! Energy over the last orbit [J], free nodes only. Balance: absorbed = emitted + to_boundary
//! + stored (up to the Newton tolerance: the sums use the scheme's own quadrature).
struct OrbitEnergy {
  double absorbed_J = 0.0;     //!< external loads + internal power
  double emitted_J = 0.0;      //!< radiated to deep space (net of the 2.7 K sink)
  double to_boundary_J = 0.0;  //!< conducted/radiated into fixed-temperature nodes
  double stored_J = 0.0;       //!< sum C (T(P) - T(0))
  double relative_imbalance() const;  //!< |absorbed - emitted - to_boundary - stored| / absorbed
};

struct PeriodicTransient {
  Eigen::VectorXd times_s;          //!< S times k P / S, k = 0..S-1
  Eigen::MatrixXd temperature_K;    //!< N x S, column k at times_s[k]
  int orbits = 0;                   //!< orbits simulated
  double periodicity_residual_K = 0.0;  //!< max |T(P) - T(0)| of the last orbit
  OrbitEnergy energy;               //!< of the last orbit
  //! N x S heater power [W] of the last orbit, column k over the step ending at times_s[k]
  //! (column 0: the last step); empty without heaters.
  Eigen::MatrixXd heater_power_W;
};

//! \param external_loads_W N x S absorbed loads [W], column k at time k P / S (periodic).
//! \param period_s orbit period P [s] (> 0).
//! \throw SolverError if a node has no path to a sink, a Newton step fails, or the orbit is
//! not periodic within the tolerance after max_orbits (says the residual reached).
//! \throw InvalidInput on bad sizes or settings.
PeriodicTransient periodic_transient(const ThermalNetwork& network,
                                     const Eigen::MatrixXd& external_loads_W, double period_s,
                                     const TransientSettings& settings = {});

//! The same on a non-uniform grid: column k of `external_loads_W` (N x K) applies at
//! times_s[k] (times_s[0] = 0, increasing, all < period_s); step k ends at times_s[k + 1]
//! (the last at period_s). Used by orbit_transient() (thermal/orbit_transient.h) to place
//! eclipse entry and exit on step boundaries. \throw as periodic_transient().
PeriodicTransient periodic_transient_on_grid(const ThermalNetwork& network,
                                             const Eigen::MatrixXd& external_loads_W,
                                             const Eigen::VectorXd& times_s, double period_s,
                                             const TransientSettings& settings = {});

}  // namespace thermodec
