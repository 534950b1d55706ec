#include "thermodec/radiation/external_geometry.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <string>

#include "thermodec/rays/embree_scene.h"
#include "thermodec/rays/sampling.h"
#include "thermodec/rays/tracing.h"
#include "thermodec/common/errors.h"
#include "thermodec/rays/surface_sides.h"

namespace thermodec {

ExternalFaces external_faces(const RayScene& scene, const ExternalSettings& settings) {
  if (settings.rays_per_face < 1)
    throw InvalidInput("external: rays per face must be >= 1 (got " + std::to_string(settings.rays_per_face) + ")");
  const Mesh& mesh = scene.mesh();
  const int nf = mesh.num_faces(), R = settings.rays_per_face;
  const auto sobol_table = tracing::shared_sobol_table(R);
  const tracing::SobolTable& sobol = *sobol_table;
  const SurfaceSides sides = surface_sides(mesh);  // identity keys: same face => same rays
  ExternalFaces out;
  out.external = Eigen::VectorXi::Zero(nf);
  std::atomic<std::int64_t> traced{0};
  tbb::parallel_for(tbb::blocked_range<int>(0, nf, 64), [&](const tbb::blocked_range<int>& r) {
    constexpr int kBatch = 16;  // small batches: most external faces escape in the first one
    alignas(16) RTCRay buf[kBatch];
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    std::int64_t count = 0;
    for (int f = r.begin(); f != r.end(); ++f) {
      const int front = sides.front_side[f];
      if (front < 0) continue;  // untraceable: dropped
      const bool test_back = settings.both_sides || sides.back_side[f] >= 0;
      bool escaped = false;
      for (int side = 0; side < (test_back ? 2 : 1) && !escaped; ++side) {
        const std::uint64_t key = sampling::hash_combine(sides.key[front], 0xe7e2000ull + side + settings.seed * 4);
        const sampling::Emitter e = sampling::make_emitter(mesh.V.row(mesh.F(f, 0)), mesh.V.row(mesh.F(f, 1)),
                                                           mesh.V.row(mesh.F(f, 2)), side == 1, key);
        for (int i = 0; i < R && !escaped;) {
          int n = 0;
          for (; i < R && n < kBatch; ++i, ++n) {
            RTCRay& ray = buf[n];
            float o[3], d[3];
            sampling::emit(e, sobol[i], false, o, d);
            ray.org_x = o[0]; ray.org_y = o[1]; ray.org_z = o[2];
            ray.dir_x = d[0]; ray.dir_y = d[1]; ray.dir_z = d[2];
            ray.tnear = 0.0f; ray.tfar = 3.0e38f;
            ray.time = 0.0f; ray.mask = 0xFFFFFFFFu; ray.id = 0; ray.flags = 0;
          }
          rtcOccluded1M(scene.impl().scene, &ctx, buf, static_cast<unsigned>(n), sizeof(RTCRay));
          count += n;
          for (int k = 0; k < n; ++k) escaped |= buf[k].tfar >= 0.0f;  // tfar = -inf when blocked
        }
      }
      out.external[f] = escaped ? 1 : 0;
    }
    traced.fetch_add(count);
  });
  out.rays_traced = traced.load();
  const int nn = static_cast<int>(mesh.node_names.size());
  out.kept_per_node = Eigen::VectorXi::Zero(nn + 1);
  out.dropped_per_node = Eigen::VectorXi::Zero(nn + 1);
  for (int f = 0; f < nf; ++f) {
    const int node = (mesh.face_node.size() > f && mesh.face_node[f] >= 0 && mesh.face_node[f] < nn) ? mesh.face_node[f] : nn;
    if (out.external[f]) {
      ++out.kept;
      ++out.kept_per_node[node];
    } else {
      ++out.dropped;
      ++out.dropped_per_node[node];
      if (sides.front_side[f] < 0) ++out.untraceable;
    }
  }
  return out;
}

Mesh extract_external(const Mesh& mesh, const ExternalFaces& external, Eigen::VectorXi* original_face) {
  if (external.external.size() != mesh.num_faces())
    throw InvalidInput("extract_external: the classification has " + std::to_string(external.external.size()) +
                       " faces, the mesh " + std::to_string(mesh.num_faces()));
  Mesh out;
  out.node_names = mesh.node_names;
  out.material_names = mesh.material_names;
  std::vector<int> new_of_old(mesh.num_vertices(), -1), faces;
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (external.external[f]) faces.push_back(f);
  int nv = 0;
  for (int f : faces)
    for (int k = 0; k < 3; ++k)
      if (new_of_old[mesh.F(f, k)] < 0) new_of_old[mesh.F(f, k)] = nv++;
  out.V.resize(nv, 3);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (new_of_old[v] >= 0) out.V.row(new_of_old[v]) = mesh.V.row(v);
  const int n = static_cast<int>(faces.size());
  out.F.resize(n, 3);
  out.face_node.resize(n);
  out.face_material.resize(n);
  out.face_back_material.resize(n);
  if (original_face) original_face->resize(n);
  for (int i = 0; i < n; ++i) {
    const int f = faces[i];
    for (int k = 0; k < 3; ++k) out.F(i, k) = new_of_old[mesh.F(f, k)];
    out.face_node[i] = mesh.face_node.size() > f ? mesh.face_node[f] : -1;
    out.face_material[i] = mesh.face_material.size() > f ? mesh.face_material[f] : -1;
    out.face_back_material[i] = mesh.face_back_material.size() > f ? mesh.face_back_material[f] : -1;
    if (original_face) (*original_face)[i] = f;
  }
  return out;
}

}  // namespace thermodec
