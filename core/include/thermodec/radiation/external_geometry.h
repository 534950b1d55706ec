#pragma once
//! External-geometry extraction (the paper's GPU z-buffer step, done with rays on the CPU):
//! a face is external if some ray leaving it escapes to infinity, i.e. it can be seen from
//! outside the spacecraft from some direction. Faces hidden inside closed solids (internal
//! walls, a box inside a box) are dropped.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "thermodec/mesh/mesh.h"
#include "thermodec/rays/ray_scene.h"

namespace thermodec {

struct ExternalSettings {
  //! Maximum rays per tested side (stops at the first escaping one). A face seen from outside
  //! through a fraction p of its (area x hemisphere) is missed with probability ~(1 - p)^rays.
  int rays_per_face = 256;
  std::uint64_t seed = 1;
  //! Also test the back of one-sided faces (for meshes whose orientation is unreliable, e.g.
  //! STL exports). Two-sided faces are always tested on both sides.
  bool both_sides = false;
};

struct ExternalFaces {
  Eigen::VectorXi external;            //!< #F 1 = visible from outside (kept), 0 = dropped
  Eigen::VectorXi kept_per_node;       //!< #nodes (+1 last: faces without a node)
  Eigen::VectorXi dropped_per_node;    //!< same
  int kept = 0;
  int dropped = 0;
  int untraceable = 0;                 //!< zero-area / non-finite faces (dropped)
  std::int64_t rays_traced = 0;
};

//! Classifies every face of scene.mesh() (uniform hemisphere directions from points spread
//! over the face, Owen-scrambled Sobol seeded per face; parallel, deterministic).
//! \throw InvalidInput if settings.rays_per_face < 1.
ExternalFaces external_faces(const RayScene& scene, const ExternalSettings& settings = {});

//! The sub-mesh of the kept faces (unused vertices removed, attributes and names kept).
//! `original_face`, if non-null, receives for each output face its index in `mesh`.
Mesh extract_external(const Mesh& mesh, const ExternalFaces& external, Eigen::VectorXi* original_face = nullptr);

}  // namespace thermodec
