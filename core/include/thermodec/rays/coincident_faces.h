#pragma once
//! Faces that overlap another face in one plane (CAD meshes: panels of two parts exported on
//! top of each other). A ray meets both at the same distance and Embree reports whichever its
//! BVH reaches first, so which one it hits depends on the rest of the scene: a reduction trial
//! (reference scene) and a full recompute (candidate scene) would disagree on rays nothing
//! changed. tracing::trace_emitter resolves such hits by a rule that depends only on the faces
//! involved (tracing::resolve_coincident).
#include <vector>

#include "thermodec/rays/embree_scene.h"

namespace thermodec::detail {

//! For each Embree primitive of `scene`, the primitives lying in the same plane (within 1e-6 of
//! the scene's size) whose triangles overlap it with positive area (sharing an edge or a
//! corner is not overlapping), as CSR: partners of p are list[begin[p] .. begin[p + 1]).
//! Found by bucketing the faces by plane, then a separating-axis test in the plane.
struct CoincidentPrims {
  std::vector<int> begin;  // #prims + 1
  std::vector<int> list;
};
CoincidentPrims coincident_prims(const RayScene::Impl& scene);

}  // namespace thermodec::detail
