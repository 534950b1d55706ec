#pragma once
//! The lumped-parameter thermal network solved by the steady and transient solvers:
//!   C_i dT_i/dt = Q_i + E_i(t) + sum_j GL_ij (T_j - T_i) + sigma sum_j GR_ij (T_j^4 - T_i^4)
//!                 + sigma GR_i,space (T_space^4 - T_i^4)
//! with Q internal power (constant, a schedule over the orbit, or a thermostat heater), E absorbed external loads, GL conductive links [W/K], GR radiative
//! couplings [m^2] (GR_ij = sum A eps B, already containing the emissivities), T_space = 2.7 K.
//! Nodes with a fixed temperature are boundary conditions; nodes with C = 0 are arithmetic.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "thermodec/nodes/thermal_model.h"
#include "thermodec/radiation/radiative_couplings.h"

namespace thermodec {

//! A thermostat heater on node `node` (Node::heater).
struct NetworkHeater {
  int node = -1;
  Thermostat thermostat;
};

//! Plain network data; N = number of nodes, node order as in ThermalModel::nodes.
struct ThermalNetwork {
  std::vector<std::string> node_names;      //!< N names (for messages and results)
  Eigen::VectorXd capacitance_J_per_K;      //!< N, >= 0; 0 = arithmetic node
  Eigen::VectorXd power_W;                  //!< N internal dissipation (constant part)
  //! N schedules over the orbit (Node::power_schedule_W; empty = none), added to power_W by
  //! thermal/internal_power.h.
  std::vector<std::vector<std::pair<double, double>>> power_schedule_W;
  std::vector<NetworkHeater> heaters;       //!< switched by the transient solver
  Eigen::VectorXd fixed_temperature_K;      //!< N, NaN = free node, else boundary temperature
  Eigen::MatrixXd conductance_W_per_K;      //!< N x N symmetric GL, diagonal ignored
  Eigen::MatrixXd radiative_couplings_m2;   //!< N x N symmetric GR, diagonal ignored
  Eigen::VectorXd to_space_couplings_m2;    //!< N GR to deep space
  double sink_temperature_K = 2.7;          //!< deep-space sink

  int num_nodes() const { return static_cast<int>(capacitance_J_per_K.size()); }
  bool is_fixed(int i) const { return fixed_temperature_K[i] == fixed_temperature_K[i]; }
};

//! Network of `model` with the radiative couplings of the radiative engine. Conductive links
//! between the same pair are summed. The GR matrix is symmetrised ((GR + GR^T)/2) so that
//! the exchange conserves energy exactly even if the engine returns a slightly asymmetric one.
//! \throw InvalidInput if the couplings' sizes differ from the model's node count, or a
//! conductance names a node out of range or is negative.
ThermalNetwork thermal_network(const ThermalModel& model, const NodeCouplings& couplings);

//! Checks sizes, finiteness and signs. \throw InvalidInput naming the node at fault.
void validate_network(const ThermalNetwork& network);

//! Names of free nodes that have no conductive or radiative path to a sink (deep space or a
//! fixed-temperature node): their temperature is undetermined in steady state and unbounded
//! over repeated orbits. Empty if every free node reaches a sink.
std::vector<std::string> nodes_without_path_to_sink(const ThermalNetwork& network);

}  // namespace thermodec
