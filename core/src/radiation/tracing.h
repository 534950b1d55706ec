#pragma once
// Private to core/src/radiation: the hot loop shared by the full and the incremental view
// factor computations. Rays are generated, traced through Embree's stream API and classified
// (which surface side was hit) without touching RayQuery.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "ray_scene_impl.h"
#include "sampling.h"
#include "thermodec/radiation/surface_sides.h"

namespace thermodec::tracing {

using SobolTable = std::vector<std::array<std::uint32_t, 4>>;

//! Emitter of side `s` of `sides` (geometry from `mesh`), seeded by its identity and `seed`.
inline sampling::Emitter side_emitter(const Mesh& mesh, const SurfaceSides& sides, int s, std::uint64_t seed) {
  const int f = sides.face[s];
  return sampling::make_emitter(mesh.V.row(mesh.F(f, 0)), mesh.V.row(mesh.F(f, 1)), mesh.V.row(mesh.F(f, 2)),
                                sides.is_back[s] != 0, sampling::hash_combine(sides.key[s], seed));
}

//! True if the ray origin + t dir, t >= 0, meets `box` (slab test; conservative at the edges).
inline bool ray_meets_box(const float* o, const float* d, const Eigen::AlignedBox3f& box) {
  float t0 = 0.0f, t1 = 3.0e38f;
  for (int k = 0; k < 3; ++k) {
    const float inv = 1.0f / d[k];  // +-inf for d = 0 is handled by IEEE rules below
    float ta = (box.min()[k] - o[k]) * inv, tb = (box.max()[k] - o[k]) * inv;
    if (d[k] == 0.0f) {
      if (o[k] < box.min()[k] || o[k] > box.max()[k]) return false;
      continue;
    }
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

//! Traces the rays of emitter `e` (all, or only those meeting `filter` when non-null) in
//! `scene`, calling on_hit(side, back_hit_on_one_sided) with side = hit side of `sides` (the
//! sides of scene's mesh) or -1 for space.
template <class OnHit>
void trace_emitter(const RayScene::Impl& scene, const SurfaceSides& sides, const sampling::Emitter& e,
                   const SobolTable& sobol, int rays, const Eigen::AlignedBox3f* filter, OnHit&& on_hit) {
  constexpr int kChunk = 64;
  alignas(16) RTCRayHit buf[kChunk];
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  int i = 0;
  while (i < rays) {
    int n = 0;
    for (; i < rays && n < kChunk; ++i) {
      float org[3], dir[3];
      sampling::emit(e, sobol[i], true, org, dir);
      if (filter && !ray_meets_box(org, dir, *filter)) continue;
      RTCRayHit& rh = buf[n++];
      rh.ray.org_x = org[0]; rh.ray.org_y = org[1]; rh.ray.org_z = org[2];
      rh.ray.dir_x = dir[0]; rh.ray.dir_y = dir[1]; rh.ray.dir_z = dir[2];
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = 3.0e38f;
      rh.ray.time = 0.0f; rh.ray.mask = 0xFFFFFFFFu; rh.ray.id = 0; rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    }
    if (n == 0) continue;
    rtcIntersect1M(scene.scene, &ctx, buf, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (int k = 0; k < n; ++k) {
      const RTCRayHit& rh = buf[k];
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        on_hit(-1, false);
        continue;
      }
      const unsigned p = rh.hit.primID;
      const int f = scene.face_of_prim[p];
      const float* nf = &scene.prim_normal[3 * p];
      const bool from_back = rh.ray.dir_x * nf[0] + rh.ray.dir_y * nf[1] + rh.ray.dir_z * nf[2] > 0.0f;
      if (from_back && sides.back_side[f] >= 0) {
        on_hit(sides.back_side[f], false);
      } else {
        on_hit(sides.front_side[f], from_back);
      }
    }
  }
}

//! Dense per-thread counter over sides + space, cleared in O(touched).
struct Counter {
  std::vector<std::int32_t> count;  // last entry = space
  std::vector<int> touched;
  std::int64_t back_hits = 0;
  explicit Counter(int num_sides) : count(num_sides + 1, 0) {}
  void add(int side, int w) {
    const int idx = side < 0 ? static_cast<int>(count.size()) - 1 : side;
    if (count[idx] == 0) touched.push_back(idx);
    count[idx] += w;
  }
};

}  // namespace thermodec::tracing
