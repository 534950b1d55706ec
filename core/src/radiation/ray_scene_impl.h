#pragma once
// Private to core/src/radiation: the Embree handles behind RayScene, for hot loops that build
// RTCRayHit records directly instead of going through RayQuery.
#include <embree3/rtcore.h>

#include <vector>

#include "thermodec/radiation/ray_scene.h"

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
