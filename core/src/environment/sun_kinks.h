#pragma once
// Private to core/src/environment: where the direct sun of a node has a kink between two orbit
// positions (a face side turning edge-on to the sun: its load alpha S A max(0, n . s) changes
// slope there), which a straight line between positions cuts off.
#include <Eigen/Core>
#include <vector>

#include "load_sides.h"
#include "thermodec/environment/orbit.h"
#include "thermodec/nodes/thermal_model.h"

namespace thermodec::load_rays {

// Sunlit instants [s] in [0, P), sorted, at most `max_knots`, where some node's direct-sun kink
// is worth a traced knot: per cell of 1/16 of a position interval h and per node, the slope
// jumps J [W/s] of its sides crossing n . s = 0 there are summed; a straight line over a kink J
// misses at most J h^2 / 8 [J] of energy, J h^2 / (8 C) [K] on a node of capacitance C (an arithmetic
// node counts 2 x threshold_K for any J). Cells where some free node's figure exceeds `threshold_K` give one
// knot each (the crossings' mean time weighted by that figure), the largest first. Cells within
// 1/16 h of a position are skipped (the position holds the kink).
std::vector<double> sun_kink_times_s(const ThermalModel& model, const std::vector<Side>& sides,
                                     const std::vector<int>& node_of_side, const Eigen::VectorXd& absorptivity,
                                     double flux_W_per_m2, int positions, double threshold_K, int max_knots);

}  // namespace thermodec::load_rays
