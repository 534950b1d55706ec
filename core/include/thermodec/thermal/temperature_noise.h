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

//! One standard deviation [K] of each node's temperature from Monte Carlo sampling, the largest
//! over the S steps: the couplings' standard errors (GR_ij, GR_i,space) and the loads' (N x S,
//! Loads::sampling_standard_error_W) propagated through the whole linearised network at each
//! step's temperatures, dT = K^-1 dQ with K the heat balance's Jacobian (conduction plus
//! 4 sigma T^3 GR, the capacitances left out: the errors come from the same samples at every step,
//! so they act as a steady offset). Unlike the node-by-node estimates above, a node whose
//! neighbours move with it is not credited with their damping. Independent errors add in
//! quadrature; a coupling's error moves the heat of both of its nodes, in opposite directions.
//! 0 for fixed nodes. `load_standard_error_W` may be empty (couplings only). Networks whose N^3 S
//! exceeds ~4e9 are evaluated at a subset of the steps (every k-th, plus the hottest).
//! \throw InvalidInput if sizes disagree.
Eigen::VectorXd temperature_noise_K(const ThermalNetwork& network, const NodeCouplings& couplings,
                                    const Eigen::MatrixXd& temperature_K, const Eigen::MatrixXd& load_standard_error_W);

//! Sample multipliers that bring each node's temperature standard error down to target_K,
//! assuming it falls as N^-3/4 (scrambled nets on discontinuous visibility): the smallest power
//! of two >= (sigma_i / target)^(4/3), within [1, max_boost]. Powers of two keep the boosts
//! stable when sigma_i moves a little (a reduction decides them once, on its reference).
std::vector<double> noise_targeted_sampling_boosts(const Eigen::VectorXd& temperature_standard_error_K,
                                                   double target_K, double max_boost = 64.0);

//! The common divisor of an oversampled model's samples: the largest power of two f with
//! sigma_i f^(3/4) <= target_K for every node with sigma_i > 0 (the same N^-3/4 law), returned
//! as the multiplier 1 / f when f >= min_thinning, at least min_boost; 1 otherwise (some node
//! at or above the target, f below min_thinning, or no noisy node). One factor for every node:
//! a node's coupling errors come from its partners' rays as much as from its own, so thinning
//! all by the same f keeps each node's estimate under the target (thinning one node alone
//! could raise a neighbour's). A 100k-face model meshed for 4000 rays per face carries
//! per-node errors of a few mK, 10x under what a 0.5 K reduction needs.
double noise_targeted_thinning(const Eigen::VectorXd& temperature_standard_error_K, double target_K,
                               double min_boost = 1.0 / 64.0, double min_thinning = 4.0);

}  // namespace thermodec
