#include "thermodec/rays/ray_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

#include "thermodec/rays/embree_scene.h"
#include "thermodec/common/errors.h"

namespace thermodec {
namespace {

// One Embree device per process: creating a device spins up its task scheduler, which is too
// expensive to repeat for every scene the reduction driver builds.
RTCDevice shared_device() {
  static RTCDevice device = [] {
    RTCDevice d = rtcNewDevice(nullptr);
    if (!d) throw Error("Embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
    return d;
  }();
  return device;
}

constexpr std::size_t kChunk = 256;  // rays per stream call: fits in L1 and amortises the call

}  // namespace

bool is_traceable_face(const Mesh& mesh, int f) {
  const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                        c = mesh.V.row(mesh.F(f, 2));
  if (!a.allFinite() || !b.allFinite() || !c.allFinite()) return false;
  const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  const double twice_area = (b - a).cross(c - a).norm();
  // note: Embree traces in float; a relative area below ~1e-12 is below what float coordinates
  // can even represent as a triangle, and such slivers would be ignored or hit erratically.
  return longest2 > 0.0 && twice_area > 1e-12 * longest2;
}

RayScene::Impl::~Impl() {
  if (scene) rtcReleaseScene(scene);
}

RayScene::RayScene(const Mesh& mesh) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.mesh = mesh;
  s.device = shared_device();
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= mesh.num_vertices())
        throw InvalidInput("RayScene: face " + std::to_string(f) + " has vertex index " +
                           std::to_string(mesh.F(f, k)) + " outside [0, " +
                           std::to_string(mesh.num_vertices()) + ")");
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (is_traceable_face(mesh, f)) {
      s.face_of_prim.push_back(f);
      const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
      const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
      for (int k = 0; k < 3; ++k) s.prim_normal.push_back(float(n[k]));
      for (int k = 0; k < 3; ++k) s.bounds.extend(Eigen::Vector3d(mesh.V.row(mesh.F(f, k))));
    } else {
      ++s.skipped;
    }
  }

  s.scene = rtcNewScene(s.device);
  rtcSetSceneFlags(s.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_HIGH);
  if (!s.face_of_prim.empty()) {
    RTCGeometry geom = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), mesh.num_vertices()));
    for (int v = 0; v < mesh.num_vertices(); ++v)
      for (int k = 0; k < 3; ++k) {
        const double x = mesh.V(v, k);
        vb[3 * v + k] = std::isfinite(x) ? static_cast<float>(x) : 0.0f;  // unused by any traced face
      }
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), s.face_of_prim.size()));
    for (std::size_t p = 0; p < s.face_of_prim.size(); ++p)
      for (int k = 0; k < 3; ++k) ib[3 * p + k] = static_cast<unsigned>(mesh.F(s.face_of_prim[p], k));
    rtcCommitGeometry(geom);
    rtcAttachGeometry(s.scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(s.scene);
  const RTCError err = rtcGetDeviceError(s.device);
  if (err != RTC_ERROR_NONE) throw Error("Embree: scene build failed (error " + std::to_string(err) + ")");
}

RayScene::~RayScene() = default;
RayScene::RayScene(RayScene&&) noexcept = default;
RayScene& RayScene::operator=(RayScene&&) noexcept = default;

const Mesh& RayScene::mesh() const { return impl_->mesh; }
int RayScene::num_traced_faces() const { return static_cast<int>(impl_->face_of_prim.size()); }
int RayScene::num_skipped_faces() const { return impl_->skipped; }
const Eigen::AlignedBox3d& RayScene::bounds() const { return impl_->bounds; }

namespace {
void fill_ray(RTCRay& r, const float* o, const float* d, float tn, float tf) {
  r.org_x = o[0]; r.org_y = o[1]; r.org_z = o[2];
  r.dir_x = d[0]; r.dir_y = d[1]; r.dir_z = d[2];
  r.tnear = tn; r.tfar = tf;
  r.time = 0.0f; r.mask = 0xFFFFFFFFu; r.id = 0; r.flags = 0;
}
}  // namespace

int RayScene::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_near,
                        double t_far, double* t_hit) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  const float o[3] = {float(origin.x()), float(origin.y()), float(origin.z())};
  const float d[3] = {float(direction.x()), float(direction.y()), float(direction.z())};
  fill_ray(rh.ray, o, d, float(t_near), float(std::min(t_far, double(std::numeric_limits<float>::max()))));
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
    if (t_hit) *t_hit = std::numeric_limits<double>::infinity();
    return -1;
  }
  if (t_hit) *t_hit = rh.ray.tfar;
  return impl_->face_of_prim[rh.hit.primID];
}

bool RayScene::occluded(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_near,
                        double t_far) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  const float o[3] = {float(origin.x()), float(origin.y()), float(origin.z())};
  const float d[3] = {float(direction.x()), float(direction.y()), float(direction.z())};
  fill_ray(r, o, d, float(t_near), float(std::min(t_far, double(std::numeric_limits<float>::max()))));
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar < 0.0f;  // Embree sets tfar = -inf on occlusion
}

void RayScene::intersect(const RayQuery* rays, std::size_t count, int* face, float* t_hit) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  alignas(16) RTCRayHit buf[kChunk];
  for (std::size_t begin = 0; begin < count; begin += kChunk) {
    const std::size_t n = std::min(kChunk, count - begin);
    for (std::size_t i = 0; i < n; ++i) {
      const RayQuery& q = rays[begin + i];
      fill_ray(buf[i].ray, q.origin, q.direction, q.t_near, q.t_far);
      buf[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
      buf[i].hit.primID = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect1M(impl_->scene, &ctx, buf, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (std::size_t i = 0; i < n; ++i) {
      const bool hit = buf[i].hit.geomID != RTC_INVALID_GEOMETRY_ID;
      face[begin + i] = hit ? impl_->face_of_prim[buf[i].hit.primID] : -1;
      if (t_hit) t_hit[begin + i] = hit ? buf[i].ray.tfar : std::numeric_limits<float>::infinity();
    }
  }
}

void RayScene::intersect(const std::vector<RayQuery>& rays, std::vector<int>& face,
                         std::vector<float>* t_hit) const {
  face.resize(rays.size());
  if (t_hit) t_hit->resize(rays.size());
  intersect(rays.data(), rays.size(), face.data(), t_hit ? t_hit->data() : nullptr);
}

void RayScene::occluded(const RayQuery* rays, std::size_t count, std::uint8_t* blocked) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  alignas(16) RTCRay buf[kChunk];
  for (std::size_t begin = 0; begin < count; begin += kChunk) {
    const std::size_t n = std::min(kChunk, count - begin);
    for (std::size_t i = 0; i < n; ++i) {
      const RayQuery& q = rays[begin + i];
      fill_ray(buf[i], q.origin, q.direction, q.t_near, q.t_far);
    }
    rtcOccluded1M(impl_->scene, &ctx, buf, static_cast<unsigned>(n), sizeof(RTCRay));
    for (std::size_t i = 0; i < n; ++i) blocked[begin + i] = buf[i].tfar < 0.0f ? 1 : 0;
  }
}

void RayScene::occluded(const std::vector<RayQuery>& rays, std::vector<std::uint8_t>& blocked) const {
  blocked.resize(rays.size());
  occluded(rays.data(), rays.size(), blocked.data());
}

}  // namespace thermodec
