#pragma once
//! The ray hot loops shared by the full and the incremental view factors (radiation/) and
//! the orbit loads (environment/): rays are generated, traced through Embree's stream API and
//! classified (which surface side was hit) without touching RayQuery; segment and box tests
//! decide which recorded rays a changed region can reach. Inline on purpose (per-ray code).
//! Includes Embree's header: for the core library's sources, not for front ends.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "thermodec/rays/coincident_faces.h"
#include "thermodec/rays/embree_scene.h"
#include "thermodec/rays/sampling.h"
#include "thermodec/rays/surface_sides.h"

namespace thermodec::tracing {

using SobolTable = std::vector<std::array<std::uint32_t, 4>>;  // sampling::sobol_4d_reversed

//! The bit-reversed Sobol table with at least n points, shared by all runs of the process (its
//! first n points do not depend on its length). Building it per call cost ~3 % of a reduction
//! trial on the sample (1e5 points, 4 x 17 XORs each).
inline std::shared_ptr<const SobolTable> shared_sobol_table(int n) {
  static std::mutex mutex;
  static std::shared_ptr<const SobolTable> cached;
  std::lock_guard<std::mutex> lock(mutex);
  if (!cached || static_cast<int>(cached->size()) < n)
    cached = std::make_shared<const SobolTable>(sampling::sobol_4d_reversed(n));
  return cached;
}

//! Emitter of side `s` of `sides` (geometry from `mesh`), seeded by its identity and `seed`.
inline sampling::Emitter side_emitter(const Mesh& mesh, const SurfaceSides& sides, int s, std::uint64_t seed) {
  const int f = sides.face[s];
  return sampling::make_emitter(mesh.V.row(mesh.F(f, 0)), mesh.V.row(mesh.F(f, 1)), mesh.V.row(mesh.F(f, 2)),
                                sides.is_back[s] != 0, sampling::hash_combine(sides.key[s], seed));
}

//! Parameter t >= 0 where the ray origin + t dir enters `box`, or +inf if it misses it
//! (slab test; conservative at the edges).
inline float ray_box_entry(const float* o, const float* d, const Eigen::AlignedBox3f& box) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  float t0 = 0.0f, t1 = kInf;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0f) {
      if (o[k] < box.min()[k] || o[k] > box.max()[k]) return kInf;
      continue;
    }
    const float inv = 1.0f / d[k];
    float ta = (box.min()[k] - o[k]) * inv, tb = (box.max()[k] - o[k]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return kInf;
  }
  return t0;
}

//! Can the segment o + t d, t in [0, len], enter `box` (bounds lo, hi)? The slab test without
//! jumps on the data (reduction trials run it on ~1e6 recorded rays each, about half of which
//! pass: branches there were mispredicted). NaN counts as entering: a slab of a zero direction
//! component met exactly at the origin, or len = NaN (read as +inf).
//! `inv_d` = 1 / d per component (rays of one direction share it: the sun's).
inline bool segment_may_enter_inv(const float* o, const float* inv_d, const float* lo, const float* hi, float len) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  float t0 = 0.0f, t1 = len == len ? len : kInf;
  for (int k = 0; k < 3; ++k) {
    const float ta = (lo[k] - o[k]) * inv_d[k], tb = (hi[k] - o[k]) * inv_d[k];
    const bool nan = ta != ta || tb != tb;
    t0 = std::max(t0, nan ? -kInf : std::min(ta, tb));
    t1 = std::min(t1, nan ? kInf : std::max(ta, tb));
  }
  return t0 <= t1;
}
inline bool segment_may_enter(const float* o, const float* d, const float* lo, const float* hi, float len) {
  const float inv_d[3] = {1.0f / d[0], 1.0f / d[1], 1.0f / d[2]};
  return segment_may_enter_inv(o, inv_d, lo, hi, len);
}

//! A reduction trial's ray that enters the changed region's box either is tested exactly
//! against the changed faces first (segment_meets) or is traced at once. The exact test pays
//! only in candidates above this many faces: in the sample (882 faces) a query in the whole
//! scene costs about what the test does (13 trials: couplings -10 %, loads -17 % without it);
//! in Juno (17001) and tdrs (19993) tracing costs more (Juno, 4 trials: loads +29 % without
//! it; tdrs, 6 trials: couplings +25 %).
constexpr int kExactChangeTestMinFaces = 4096;
inline bool exact_change_test_pays(int candidate_faces) { return candidate_faces > kExactChangeTestMinFaces; }

//! True if the segment origin + t dir, t in [0, t_max], meets a face of `scene` (the exact
//! changed-face test of the reuse paths: `scene` holds only the removed and added faces).
inline bool segment_meets(const RayScene::Impl& scene, const float* o, const float* d, float t_max) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay ray;
  ray.org_x = o[0]; ray.org_y = o[1]; ray.org_z = o[2];
  ray.dir_x = d[0]; ray.dir_y = d[1]; ray.dir_z = d[2];
  ray.tnear = 0.0f;
  ray.tfar = t_max;
  ray.time = 0.0f; ray.mask = 0xFFFFFFFFu; ray.id = 0; ray.flags = 0;
  rtcOccluded1(scene.scene, &ctx, &ray);
  return ray.tfar < 0.0f;
}

//! Per Embree primitive, what the hot loop needs to classify a hit, packed in one cache line
//! access: unit front normal and the surface sides of its face.
struct PrimInfo {
  float n[3];
  int front;  // side index of the face's front
  int back;   // side index of its back, -1 if one-sided
  int coincident_begin = 0, coincident_end = 0;  // its partners in PrimTable::coincident
};
//! Whether a ray along `d` stops on the primitive: it meets its front, or its face has a back
//! side (the back of a one-sided face neither emits nor absorbs: the ray passes on).
inline bool takes_ray(const PrimInfo& pi, const float* d) {
  return !(d[0] * pi.n[0] + d[1] * pi.n[1] + d[2] * pi.n[2] > 0.0f) || pi.back >= 0;
}
//! The hit classification of a scene: per primitive its PrimInfo and, for primitives that
//! overlap others in one plane (coincident_faces.h), those partners, their triangles and a
//! stable identity, so that a hit on such a group is resolved the same in every scene.
struct PrimTable {
  std::vector<PrimInfo> info;
  std::vector<int> coincident;                 // partner primitives (CSR, see PrimInfo)
  std::vector<std::array<float, 12>> triangle;  // per primitive: a, b, c, N / |N|^2 (N = (b - a) x (c - a))
  std::vector<std::uint64_t> key;              // per primitive: its front side's key
  const PrimInfo& operator[](std::size_t p) const { return info[p]; }
  std::size_t size() const { return info.size(); }
};

inline PrimTable prim_table(const RayScene::Impl& scene, const SurfaceSides& sides) {
  PrimTable t;
  t.info.resize(scene.face_of_prim.size());
  detail::CoincidentPrims co = detail::coincident_prims(scene);
  t.coincident = std::move(co.list);
  if (!t.coincident.empty()) {
    t.triangle.resize(t.info.size());
    t.key.resize(t.info.size());
  }
  for (std::size_t p = 0; p < t.info.size(); ++p) {
    const int f = scene.face_of_prim[p];
    for (int k = 0; k < 3; ++k) t.info[p].n[k] = scene.prim_normal[3 * p + k];
    t.info[p].front = sides.front_side[f];
    t.info[p].back = sides.back_side[f];
    t.info[p].coincident_begin = co.begin[p];
    t.info[p].coincident_end = co.begin[p + 1];
    if (t.coincident.empty()) continue;
    Eigen::Vector3f v[3];
    for (int k = 0; k < 3; ++k) v[k] = scene.mesh.V.row(scene.mesh.F(f, k)).transpose().cast<float>();
    const Eigen::Vector3f N = (v[1] - v[0]).cross(v[2] - v[0]);
    const Eigen::Vector3f Ns = N / std::max(N.squaredNorm(), std::numeric_limits<float>::min());
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) t.triangle[p][3 * k + j] = v[k][j];
    for (int j = 0; j < 3; ++j) t.triangle[p][9 + j] = Ns[j];
    t.key[p] = sides.key[sides.front_side[f]];
  }
  return t;
}

//! Per side: 1 if its face overlaps another face in one plane (a coincident group), whose hits
//! the tie rule resolves (resolve_coincident).
inline std::vector<char> coincident_side_flags(const PrimTable& t, int num_sides) {
  std::vector<char> flag(num_sides, 0);
  if (t.coincident.empty()) return flag;
  for (std::size_t p = 0; p < t.size(); ++p)
    if (t[p].coincident_begin != t[p].coincident_end)
      for (int s : {t[p].front, t[p].back})
        if (s >= 0 && s < num_sides) flag[s] = 1;
  return flag;
}

//! A ray o + t d reached primitive `hit` at distance t. If that primitive overlaps others in
//! its plane, the hit goes to the member of the group that contains the hit point and takes
//! the ray (its front faces the ray, or it has a back side) with the smallest key; if none
//! takes it (all are one-sided backs), `hit` is returned and the caller lets the ray pass.
//! The choice depends only on the group's faces, not on which of them Embree reported.
inline unsigned resolve_coincident(const PrimTable& prims, unsigned hit, const float* o, const float* d, float t) {
  const PrimInfo& h = prims[hit];
  if (h.coincident_begin == h.coincident_end) return hit;
  const float p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
  auto contains = [&](unsigned q) {
    const auto& tr = prims.triangle[q];
    const float* N = tr.data() + 9;
    float w_sum = 0.0f;
    for (int k = 0; k < 2; ++k) {  // barycentric weights of corners k = 0, 1 (the third closes the sum)
      const float* b = tr.data() + 3 * ((k + 1) % 3);
      const float* c = tr.data() + 3 * ((k + 2) % 3);
      const float e[3] = {c[0] - b[0], c[1] - b[1], c[2] - b[2]}, q2[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
      const float cr[3] = {e[1] * q2[2] - e[2] * q2[1], e[2] * q2[0] - e[0] * q2[2], e[0] * q2[1] - e[1] * q2[0]};
      const float w = cr[0] * N[0] + cr[1] * N[1] + cr[2] * N[2];
      if (w < -1e-5f) return false;
      w_sum += w;
    }
    return 1.0f - w_sum >= -1e-5f;
  };
  unsigned best = hit;
  bool found = false;
  auto consider = [&](unsigned q) {
    if (!takes_ray(prims[q], d) || !contains(q)) return;
    if (!found || prims.key[q] < prims.key[best] || (prims.key[q] == prims.key[best] && q < best)) best = q;
    found = true;
  };
  consider(hit);
  for (int k = h.coincident_begin; k < h.coincident_end; ++k) consider(static_cast<unsigned>(prims.coincident[k]));
  return best;
}

//! Accept-all ray filter.
struct AllRays {
  bool operator()(int) const { return true; }
  bool operator()(int, const float*, const float*) const { return true; }
};

//! Traces the rays i in [0, rays) (or i = order[k], k in [0, rays), if `order` is given) of
//! emitter `e` accepted by pre(i) and then by
//! keep(i, origin, direction) in
//! `scene`, calling on_hit(i, side, crossed, t) in ray order, with side = hit side of `sides`
//! (the sides of scene's mesh) or -1 for space (t = +inf), and crossed = the ray passed
//! through the back of a one-sided face on its way. With `ray_of`, i is a position and the ray
//! traced there is the emitter's ray ray_of[i] (records kept in another order than the rays').
template <class Keep, class OnHit, class Pre = AllRays>
void trace_emitter(const RayScene::Impl& scene, const PrimTable& prims, const sampling::Emitter& e,
                   const SobolTable& sobol, int rays, Keep&& keep, OnHit&& on_hit, Pre&& pre = Pre{},
                   const std::uint32_t* order = nullptr, const std::uint32_t* ray_of = nullptr) {
  constexpr int kChunk = 64;
  alignas(16) RTCRayHit buf[kChunk];
  int index[kChunk];
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  int k = 0;
  while (k < rays) {
    int n = 0;
    for (; k < rays && n < kChunk; ++k) {
      const int i = order ? static_cast<int>(order[k]) : k;
      if (!pre(i)) continue;  // decided without generating the ray
      float org[3], dir[3];
      sampling::emit(e, sobol[ray_of ? ray_of[i] : i], true, org, dir);
      if (!keep(i, org, dir)) continue;
      index[n] = i;
      RTCRayHit& rh = buf[n++];
      rh.ray.org_x = org[0]; rh.ray.org_y = org[1]; rh.ray.org_z = org[2];
      rh.ray.dir_x = dir[0]; rh.ray.dir_y = dir[1]; rh.ray.dir_z = dir[2];
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = std::numeric_limits<float>::infinity();
      rh.ray.time = 0.0f; rh.ray.mask = 0xFFFFFFFFu; rh.ray.id = 0; rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    }
    if (n == 0) continue;
    rtcIntersect1M(scene.scene, &ctx, buf, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (int m = 0; m < n; ++m) {
      RTCRayHit& rh = buf[m];
      bool crossed = false;
      // The back of a one-sided face neither emits nor absorbs (Mesh::face_back_material):
      // a ray reaching it passes through and goes on. A closed, consistently oriented model
      // never gets here; an open one (e.g. a CAD sheet exported one-sided) stays reciprocal.
      for (int pass = 0; pass < 64; ++pass) {
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
        const float dir[3] = {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z};
        if (!prims.coincident.empty()) {
          const float o[3] = {rh.ray.org_x, rh.ray.org_y, rh.ray.org_z};
          rh.hit.primID = resolve_coincident(prims, rh.hit.primID, o, dir, rh.ray.tfar);
        }
        if (takes_ray(prims[rh.hit.primID], dir)) break;
        crossed = true;
        const float t = rh.ray.tfar;
        rh.ray.tnear = t + std::max(1e-6f * t, 1e-30f);
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene.scene, &ctx, &rh);
      }
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        on_hit(index[m], -1, crossed, std::numeric_limits<float>::infinity());
        continue;
      }
      const PrimInfo& pi = prims[rh.hit.primID];
      const bool from_back = rh.ray.dir_x * pi.n[0] + rh.ray.dir_y * pi.n[1] + rh.ray.dir_z * pi.n[2] > 0.0f;
      // from_back on a one-sided face here only if 64 crossings were not enough (pathological):
      // counted on its front.
      on_hit(index[m], from_back && pi.back >= 0 ? pi.back : pi.front, crossed, rh.ray.tfar);
    }
  }
}

//! What one reference ray hit: code = 0 (space) or 2 (side + 1), + 1 if it crossed a back;
//! t = hit distance [m] (+inf for space).
struct RayRecord {
  std::int32_t code;
  float t;
  int side() const { return code / 2 - 1; }  // -1 = space
  bool back() const { return (code & 1) != 0; }
  static RayRecord of(int side, bool back, float t) { return {2 * (side + 1) + (back ? 1 : 0), t}; }
};

//! Dense per-thread counter over sides + space (+ a "gone" bucket used by the incremental
//! path for hits on reference faces that no longer exist), cleared in O(touched).
struct Counter {
  std::vector<std::int32_t> count;  // [0, n) sides, n = space, n + 1 = gone
  std::vector<int> touched;
  int num_sides;
  explicit Counter(int n) : count(n + 2, 0), num_sides(n) {}
  int space() const { return num_sides; }
  int gone() const { return num_sides + 1; }
  void add(int side, int w) {
    const int idx = side < 0 ? space() : side;
    if (count[idx] == 0) touched.push_back(idx);  // may repeat if a count returns to 0
    count[idx] += w;
  }
};

}  // namespace thermodec::tracing
