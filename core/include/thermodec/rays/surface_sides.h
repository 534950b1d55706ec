#pragma once
//! The radiating surface sides of a mesh: the front of every traceable face, plus the back of
//! every two-sided face (Mesh::face_back_material >= 0) as a separate side with its own
//! material. Each side has a stable identity (a hash of its vertex coordinates and side), the
//! seed of its rays: an unchanged face keeps the same rays in a modified model.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "thermodec/nodes/thermal_model.h"

namespace thermodec {

struct SurfaceSides {
  Eigen::VectorXi face;      //!< #S mesh face of each side
  Eigen::VectorXi is_back;   //!< #S 1 = back side of a two-sided face, 0 = front
  Eigen::VectorXi node;      //!< #S thermal node (Mesh::face_node), may be -1
  Eigen::VectorXi material;  //!< #S material index (-1 if unresolved, e.g. a bare Mesh)
  Eigen::VectorXd area_m2;   //!< #S area [m^2]
  //! #S identity: hash of the face's vertex coordinates (in F order), side, sidedness, and
  //! its occurrence number among identical faces. Independent of the face index.
  std::vector<std::uint64_t> key;
  Eigen::VectorXd ir_boost;    //!< #S IR ray multiplier of the side's node (Node::sampling_boost.ir)
  Eigen::VectorXd load_boost;  //!< #S sun/Earth sample multiplier of the side's node (.loads)
  Eigen::VectorXi front_side;  //!< #F side index of each face's front, -1 if untraceable
  Eigen::VectorXi back_side;   //!< #F side index of each face's back, -1 if one-sided

  int size() const { return static_cast<int>(face.size()); }
};

//! Sides of a bare mesh (materials are the mesh's face_material / face_back_material).
SurfaceSides surface_sides(const Mesh& mesh);

//! Sides of a model, with materials resolved (face -> node default -> model default).
//! \throw InvalidInput if a face names a node or material the model does not have.
SurfaceSides surface_sides(const ThermalModel& model);

//! Per-side emissivity (IR) or absorptivity (solar) of `model`'s materials.
//! \throw InvalidInput if a side has no material.
Eigen::VectorXd side_emissivity(const ThermalModel& model, const SurfaceSides& sides);
Eigen::VectorXd side_absorptivity(const ThermalModel& model, const SurfaceSides& sides);

//! Rays per side when the fronts of a node must get at least min_rays_per_node in total (and
//! so must its backs if two-sided), shared in proportion to area: max(rays_per_side,
//! ceil(min_rays_per_node x A_side / A_node)), A_node rounded to 1/64 octave; sides without a
//! node get rays_per_side. A side's count depends on its own area and its node's area only, so
//! it stays the same when other faces of its node change (decimation keeps node areas).
//! Both counts are multiplied by the side's `boost` (SurfaceSides::ir_boost or load_boost;
//! empty = 1), then rounded to a power of two, 2^m or 2^(m+1) for 2^m <= r < 2^(m+1), up when
//! r >= 2^m / ln 2 (counts spread evenly in log keep their mean): a side's samples are the
//! first points of its Owen-scrambled Sobol sequence (rays/sampling.h), a complete net only
//! at 2^m points. Returns #S (min_rays_per_node <= 0: rays_per_side for all).
Eigen::VectorXi rays_per_side_of_node(const SurfaceSides& sides, int rays_per_side, int min_rays_per_node,
                                      const Eigen::VectorXd& boost = Eigen::VectorXd());

}  // namespace thermodec
