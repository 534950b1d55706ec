#pragma once
//! The Embree handles behind RayScene, for the core's hot loops (rays/tracing.h, the view
//! factors, the orbit loads) that build RTCRayHit records directly instead of going through
//! RayQuery. Includes Embree's header: for the core library's sources, not for front ends.
#include <embree3/rtcore.h>

#include <vector>

#include "thermodec/rays/ray_scene.h"

namespace thermodec {

struct RayScene::Impl {
  Mesh mesh;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<int> face_of_prim;  // Embree primID -> mesh face
  std::vector<float> prim_normal;  // 3 per primID: unit front normal (CCW), for side tests
  int skipped = 0;
  Eigen::AlignedBox3d bounds;
  ~Impl();
};

}  // namespace thermodec
