#pragma once
//! The thermal network of one simulated model in the form other thermal solvers take it
//! (ESATAN-TMS, SINDA/FLUINT, CSV tables): nodes with capacitance, internal power, boundary
//! temperature, radiating area and area-weighted alpha/eps; GL [W/K] and GR [m^2] couplings; the
//! absorbed external loads per node as a time table [W] over one orbit. SI throughout: m, K, W,
//! J/K, W/K, s. Built from the same network and loads `thermodec simulate` solves, so a solver
//! that reads the exported file and integrates it the same way gets the same temperatures.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "thermodec/nodes/thermal_model.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/thermal/network.h"
#include "thermodec/thermal/simulate.h"

namespace thermodec {

struct ExportedNetwork {
  std::string title;                  //!< one line, e.g. the model path
  //! C, Q, fixed T, GL, GR, GR to space, sink 2.7 K; Q's schedules and thermostat heaters
  //! (transient; a steady export holds their orbit mean in power_W, without schedules).
  ThermalNetwork network;
  Eigen::VectorXd area_m2;            //!< N radiating area (front sides; both for two-sided faces)
  Eigen::VectorXd absorptivity;       //!< N area-weighted solar absorptivity of the node's sides
  Eigen::VectorXd emissivity;         //!< N area-weighted IR emissivity
  bool transient = false;             //!< orbit-periodic transient (else steady)
  double period_s = 0.0;              //!< orbit period [s]; 0 for steady
  int orbits = 0;                     //!< transient: orbits `simulate` ran to reach periodicity
  Eigen::VectorXd times_s;            //!< S load times (k P / S; one 0 for steady)
  Eigen::MatrixXd solar_W;            //!< N x S direct + reflected solar absorbed
  Eigen::MatrixXd albedo_W;           //!< N x S Earth-albedo absorbed
  Eigen::MatrixXd earth_ir_W;         //!< N x S Earth-IR absorbed
  Eigen::MatrixXd temperature_K;      //!< N x S temperatures `simulate` found (initial T = column 0)
  //! The load tables the writers export (transient), K points over [0, P): the positions, the
  //! loads' other sunlit knots (Loads::knot_times_s) and, at every eclipse switch, two points,
  //! the value just before and kSwitchRamp_s after it, so
  //! that a tool interpolating the table linearly (ESATAN INTCY1, SINDA D11CYL) applies the
  //! loads `simulate` integrates (thermal/orbit_transient.h, loads_at) to within that ramp.
  Eigen::VectorXd table_times_s;
  Eigen::MatrixXd table_solar_W, table_albedo_W, table_earth_ir_W;  //!< N x K, as solar_W ...
  static constexpr double kSwitchRamp_s = 1e-3;
  //! N x K total external load of the tables [W].
  Eigen::MatrixXd table_external_W() const { return table_solar_W + table_albedo_W + table_earth_ir_W; }
  //! One comment block (lines without a comment marker) that travels in every export's header:
  //! a reduced model's certificate (nodes/thermal_model.h, ThermalModel::certificate); empty if none.
  std::vector<std::string> provenance;
  //! N x S total external load [W] (solar + albedo + Earth IR).
  Eigen::MatrixXd external_W() const { return solar_W + albedo_W + earth_ir_W; }
  int num_nodes() const { return network.num_nodes(); }
};

//! A node's power schedule (Node::power_schedule_W) as a cyclic doublet table (t [s], W) over
//! [0, P] for a tool that interpolates linearly (ESATAN INTCY1, SINDA D11CYL): each value held
//! to kSwitchRamp_s before the next time, the first point repeated at P. Empty for no schedule.
std::vector<std::pair<double, double>> schedule_doublets(const std::vector<std::pair<double, double>>& schedule,
                                                         double period_s);

//! The exported network of `model` simulated as `result` with `couplings` (simulate_model's
//! couplings_out). \throw InvalidInput if the sizes disagree.
ExportedNetwork exported_network(const ThermalModel& model, const NodeCouplings& couplings,
                                 const SimulationResult& result, const std::string& title);

}  // namespace thermodec
