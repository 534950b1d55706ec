#pragma once
//! One thermal simulation of a model: network from the model and its radiative couplings,
//! loads from its environment, steady or orbit-periodic transient temperatures.
//!
//! Split for reuse: radiative_couplings() (radiation stage) and external_loads()
//! (environment stage) are computed by the caller and passed in, so a driver that changes
//! one node can recompute only what that change affects and call simulate() again (the
//! network solve itself takes milliseconds).
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "thermodec/environment/loads.h"
#include "thermodec/nodes/thermal_model.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/thermal/network.h"
#include "thermodec/thermal/orbit_transient.h"
#include "thermodec/thermal/steady_state.h"
#include "thermodec/thermal/transient.h"

namespace thermodec {

struct SimulationSettings {
  TransientSettings transient;  //!< max_orbits < 1 here means: use model.analysis.orbits
  NewtonSettings newton;        //!< steady-state Newton settings
  //! Time integration of an orbit; time_tolerance_K <= 0 here means: model.analysis.time_tolerance_K
  OrbitTimeSettings time;
  //! Estimate SimulationResult::orbit_sampling_error_K (a transient: one more solve, from every
  //! other position). Off here so that the reduction's trials, which compare like with like,
  //! do not pay for it; simulate_model (what `simulate` and `export` run) turns it on.
  bool orbit_sampling_error = false;
  SimulationSettings() { transient.max_orbits = 0; time.time_tolerance_K = 0.0; }
};

//! Result of one simulation; N nodes (model order), S times.
struct SimulationResult {
  std::vector<std::string> nodes;
  Eigen::VectorXd times_s;          //!< S
  Eigen::MatrixXd temperature_K;    //!< N x S
  Loads loads;                      //!< absorbed external loads used (N x S per component)
  Eigen::VectorXd internal_power_W; //!< N, orbit mean (constant power + schedules)
  Eigen::VectorXd heater_power_W;   //!< N orbit-mean thermostat heater power (transient); empty without heaters
  bool transient = false;
  int orbits = 0;                       //!< transient: orbits simulated
  double periodicity_residual_K = 0.0;  //!< transient: max |T(P) - T(0)|
  OrbitEnergy energy;                   //!< transient: energy balance of the last orbit (finest grid)
  double time_error_K = 0.0;            //!< transient: estimated time-discretization error (max over nodes, times)
  int solver_steps_per_orbit = 0;       //!< transient: steps of the finest solver grid
  //! Orbit: estimated error [K] from sampling the loads at S positions (max over nodes and
  //! times): |T(S) - T(S/2)| / 3 at the shared positions, Richardson's estimate for the
  //! second-order piecewise-linear interpolation between positions (the same solve with every
  //! other position). 0 when not estimated (SimulationSettings::orbit_sampling_error off, fixed
  //! sun, S odd or < 4).
  double orbit_sampling_error_K = 0.0;
  //! N: one standard deviation [K] of each node's temperature from Monte Carlo sampling, the
  //! largest over the times (thermal/temperature_noise.h, temperature_noise_K: the couplings'
  //! and the loads' standard errors through the linearised network). Empty if not estimated.
  Eigen::VectorXd noise_K;
};

//! Steady analysis (or a fixed sun): steady state of the time-averaged loads, one time 0.
//! transient_orbit with an orbit: periodic transient (orbit_transient) at loads.times_s.
//! \throw InvalidInput if sizes disagree; SolverError from the solvers.
SimulationResult simulate(const ThermalModel& model, const NodeCouplings& couplings,
                          const Loads& loads, const SimulationSettings& settings = {});

//! Largest temperature difference between two results.
struct TemperatureDifference {
  double max_abs_K = 0.0;  //!< max over nodes and times of |T_a - T_b| [K]
  std::string node;        //!< where it occurs
  double time_s = 0.0;
  int time_index = 0;
  //! Per node of the first result (its order): max over times of |T_a - T_b| [K] and the
  //! time [s] where it occurs.
  struct PerNode {
    std::string node;
    double max_abs_K = 0.0;
    double time_s = 0.0;
  };
  std::vector<PerNode> per_node;
};

//! Compares results with the same node names (matched by name, any order) and the same
//! times. \throw InvalidInput naming a node missing from one side, or if the times differ.
TemperatureDifference compare_results(const SimulationResult& a, const SimulationResult& b);

}  // namespace thermodec
