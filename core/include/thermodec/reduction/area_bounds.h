#pragma once
//! How far each node's area may drift in a decimation, from how much the temperatures depend
//! on it in the reference (docs/decimation.md, "Per-node area bound").
#include <Eigen/Core>
#include <vector>

#include "thermodec/thermal/network.h"

namespace thermodec {

//! Per node i, the largest first-order temperature change [K] of any node per unit relative
//! change of node i's area, over the reference's times. Node i radiates through Gebhart
//! couplings that all scale with its area (GR_ij, GR_i,space), while what it absorbs from the
//! Sun and the planet goes through its projected area, which a collapse inside the node leaves
//! unchanged to first order (the area vectors of a star sum to a vector set by its outline).
//! Growing the area by a fraction a at fixed temperatures adds a sigma (GR_i,space (T_i^4 -
//! T_sink^4) + sum_j GR_ij (T_i^4 - T_j^4)) to node i's losses and a sigma GR_ij (T_j^4 - T_i^4)
//! to each node j's; the network's linearised conductance matrix (radiative 4 sigma T^3 GR and
//! conductive GL, fixed nodes held) turns them into the temperature changes. Quasi-steady:
//! heat capacities only damp the response. A node alone in space gets T_i / 4 (dT = T dA/4A);
//! a node in radiative balance with its surroundings (an enclosed panel, a shaded inner face)
//! gets far less: its temperature follows its surroundings whatever its area. Linear algebra
//! of N x N per time: on networks of hundreds of nodes every k-th time only (N^3 S <= 5e9).
//! \param temperature_K N x S reference temperatures [K].
//! \throw InvalidInput if sizes disagree.
Eigen::VectorXd area_sensitivity_K(const ThermalNetwork& network, const Eigen::MatrixXd& temperature_K);

//! Per node, the relative area change that moves the temperatures by at most `budget_K` at
//! first order (budget_K / area_sensitivity_K), at most `cap` (also where the sensitivity is 0).
std::vector<double> node_area_bounds(const Eigen::VectorXd& sensitivity_K, double budget_K, double cap);

}  // namespace thermodec
