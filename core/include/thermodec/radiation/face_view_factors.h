#pragma once
//! Face-level (surface-side-level) view factors by Monte Carlo ray tracing with Embree.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>

#include "thermodec/nodes/thermal_model.h"
#include "thermodec/radiation/planar_strata.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/surface_sides.h"

namespace thermodec {

//! Sparse side-to-side view factors. Side s emits side_rays[s] rays (side_ray_counts()):
//! origins uniform on the triangle, directions cosine-weighted over its hemisphere, the first
//! side_rays[s] points of a per-side Owen-scrambled 4-D Sobol sequence seeded by the side's
//! identity and RadiationSettings::seed (so a side's rays depend only on its identity, the
//! seed and its ray count).
struct FaceViewFactors {
  SurfaceSides sides;
  //! #S x #S: F(s, t) = fraction of the rays of side s whose first hit is side t [-], or for
  //! a side in `controlled` the same rays weighed by its planar control variates
  //! (planar_strata.h). The back of a one-sided face neither emits nor absorbs: rays pass
  //! through it (see docs).
  Eigen::SparseMatrix<double, Eigen::RowMajor> F;
  Eigen::VectorXd to_space;  //!< #S fraction of rays escaping to infinity [-]
  int rays_per_side = 0;      //!< RadiationSettings::rays_per_face (side_rays: the counts emitted)
  //! #S rays emitted by each side; empty = rays_per_side for all (hand-built results).
  Eigen::VectorXi side_rays;
  std::int64_t rays_traced = 0;
  std::int64_t back_hits_on_one_sided = 0;  //!< rays that passed through the back of a one-sided face
  Eigen::VectorXi back_hits_per_side;        //!< #S the same, per emitting side
  //! #S (or empty: none) sides whose rows are regression estimates with planar control
  //! variates (RadiationSettings::planar_strata); strata.count = 0 for a plain row.
  std::vector<ControlledSide> controlled;
};

//! Rays each side emits: max(rays_per_face, ceil(min_rays_per_node / n)) for a side of a node
//! with n sides in `sides`, rays_per_face for sides without a node. Returns #S.
//! \throw InvalidInput if settings.rays_per_face < 1 or min_rays_per_node < 0.
Eigen::VectorXi side_ray_counts(const SurfaceSides& sides, const RadiationSettings& settings);

//! Traces all sides of `sides` (which must be the sides of scene.mesh()) in parallel (TBB).
//! The result is bit-identical for any thread count.
//! \throw InvalidInput if settings.rays_per_face < 1.
FaceViewFactors face_view_factors(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings);

//! Same with the sides of scene.mesh() (materials as stored in the mesh).
FaceViewFactors face_view_factors(const RayScene& scene, const RadiationSettings& settings);

}  // namespace thermodec
