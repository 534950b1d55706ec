#pragma once
//! How much Monte Carlo noise moves each node's temperature, and which nodes therefore deserve
//! more samples (Node::sampling_boost).
//!
//! First order, node by node: an error dQ_i [W] in the net heat into node i moves its
//! temperature by dT_i = dQ_i / G_i, G_i = dQ_i/dT_i = 4 sigma T_i^3 (sum_j GR_ij + GR_i,space)
//! + sum_j GL_ij [W/K] (its neighbours held fixed). A coupling error dGR_ij [m^2] gives
//! dQ_i = sigma dGR_ij (T_j^4 - T_i^4), dGR_i,space gives -sigma dGR_i,space T_i^4; a load
//! error is dQ_i itself. Independent errors add in quadrature. The standard errors are
//! binomial; scrambled Sobol points do better (measured ~2-5x on the sample), so the estimate
//! ranks nodes and bounds their noise rather than predicting it.
#include <Eigen/Core>
#include <vector>

#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/thermal/network.h"

namespace thermodec {

//! Standard error of each node's temperature [K] caused by the couplings' standard errors, at
//! the temperatures T_K (N x S: nodes x orbit steps), the largest over the steps. 0 for fixed
//! nodes. \throw InvalidInput if sizes disagree.
Eigen::VectorXd temperature_standard_error_K(const ThermalNetwork& network, const NodeCouplings& couplings,
                                            const Eigen::MatrixXd& temperature_K);

//! The same for load errors: load_standard_error_W (N x S, Loads::sampling_standard_error_W)
//! divided by G_i, the largest over the steps.
Eigen::VectorXd temperature_standard_error_from_loads_K(const ThermalNetwork& network,
                                                       const Eigen::MatrixXd& temperature_K,
                                                       const Eigen::MatrixXd& load_standard_error_W);

//! Sample multipliers that bring each node's temperature standard error down to target_K,
//! assuming it falls as N^-3/4 (scrambled nets on discontinuous visibility): the smallest power
//! of two >= (sigma_i / target)^(4/3), within [1, max_boost]. Powers of two keep the boosts
//! stable when sigma_i moves a little (a reduction decides them once, on its reference).
std::vector<double> noise_targeted_sampling_boosts(const Eigen::VectorXd& temperature_standard_error_K,
                                                   double target_K, double max_boost = 64.0);

}  // namespace thermodec
