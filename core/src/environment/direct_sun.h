#pragma once
// Private to core/src/environment: the sunlit fraction of each face side's sample points.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "load_sides.h"
#include "occluders.h"
#include "ray_records.h"
#include "thermodec/radiation/planar_strata.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/surface_sides.h"
#include "thermodec/rays/tracing.h"

namespace thermodec::load_rays {

// Unblocked fraction of each side's sample points towards the direction `toward` (unit),
// for sides facing it; 0 for the others. A pilot of the first P Sobol points (P a power of 2:
// one per 1/P-area stratum of the Owen-scrambled net) decides fully lit or fully shadowed
// sides; only sides where the pilot disagrees trace all `rays`. note: a shadow that slips
// between all P pilot points is missed; it then covers well under 1/P of the face (measured on
// the sample: P = 16 left 0.6 W seed-to-seed differences on single nodes, P = 64 < 0.2 W).
// `origins` (per side, filled on first use): the sample points, kept for the next pass unless
// the caller clears them (a pass with its own seed draws its own points). `controls` (a run that
// keeps no records): the hulls whose crossings post-stratify the partly lit sides' points
// (shadow_controls.h); the pilot still decides fully lit or shadowed sides.
Eigen::VectorXd sunlit_fraction(const RayScene& scene, const std::vector<Side>& geo, const SurfaceSides& sides,
                                const Eigen::Vector3d& toward, const Eigen::VectorXi& side_rays, int pilot_rays,
                                std::uint64_t seed, const tracing::SobolTable& sobol, const Occluders& occ,
                                const PassContext& pass, std::vector<std::vector<std::array<float, 3>>>& origins,
                                const std::vector<char>* todo = nullptr, const std::vector<NodeHull>* controls = nullptr);

}  // namespace thermodec::load_rays
