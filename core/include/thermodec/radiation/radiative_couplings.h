#pragma once
//! Node-to-node IR radiative couplings of a diffuse grey model.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "thermodec/nodes/thermal_model.h"

namespace thermodec {

//! Aggregated node quantities; row i = from node i, node order as in ThermalModel::nodes.
struct NodeCouplings {
  Eigen::VectorXd area_m2;                  //!< radiating area per node [m^2]
  Eigen::MatrixXd view_factors;             //!< F_ij, area-weighted over the node's faces [-]
  Eigen::VectorXd to_space;                 //!< F_i,space [-]
  Eigen::MatrixXd radiative_couplings_m2;   //!< GR_ij = sum A_k eps_k B_kl [m^2], symmetric
  Eigen::VectorXd to_space_couplings_m2;    //!< GR_i,space [m^2]
  Eigen::MatrixXd view_factors_standard_error;          //!< Monte Carlo 1-sigma of F_ij
  Eigen::MatrixXd radiative_couplings_standard_error;   //!< Monte Carlo 1-sigma of GR_ij [m^2]
};

//! Computes node couplings by Monte Carlo ray tracing with Embree; deterministic for a seed.
//! \throw InvalidInput if settings.rays_per_face < 1.
NodeCouplings radiative_couplings(const ThermalModel& model, const RadiationSettings& settings);

}  // namespace thermodec
