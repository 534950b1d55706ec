#pragma once
// Private to core/src/environment: planar control variates for the sunlit fraction of a face
// side (docs/environment.md, "Shadow control variates"), the direct sun's counterpart of the
// view factors' (radiation/planar_strata.h).
//
// A shadow ray leaves the side's sample point x along the sun direction d. It crosses the hull
// P of a flat node (or the aperture of the side's own concave cap) iff x lies in the parallel
// projection of P along -d onto the side's plane, so the share of the side's points whose rays
// cross every hull of a set T is the area of the triangle clipped by those projections, over
// the triangle's area: exact, no quadrature. The lit fraction is then post-stratified by the
// set of hulls each ray crosses (stratum_weights): a shadow cast by flat nodes, or a cap's
// shadow on itself, no longer depends on which points the seed drew.
#include <Eigen/Core>
#include <vector>

#include "load_sides.h"
#include "thermodec/radiation/planar_strata.h"

namespace thermodec::load_rays {

// The share [-] of the lifted triangle g whose rays along `toward` (unit, g.normal . toward >
// 0) cross every polygon of `ps` (planar, convex, vertices in order) at a positive distance.
double shadow_share(const Side& g, const Eigen::Vector3d& toward, const std::vector<std::vector<Eigen::Vector3d>>& ps);

// The control hulls of side g (of node `node`) along `toward`: the flat hulls of other nodes
// and the apertures of its own whose share lies in [1e-3, 1 - 1e-3], the largest
// kMaxStrataPerSide, with the joint shares of every set of them. count 0 if none.
SideStrata shadow_strata(const Side& g, int node, const Eigen::Vector3d& toward, const std::vector<NodeHull>& hulls);

}  // namespace thermodec::load_rays
