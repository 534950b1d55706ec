#include "thermodec/radiation/face_view_factors.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

#include "thermodec/rays/tracing.h"
#include "thermodec/common/errors.h"
#include "view_factor_rows.h"

namespace thermodec {

Eigen::VectorXi side_ray_counts(const SurfaceSides& sides, const RadiationSettings& settings) {
  if (settings.rays_per_face < 1)
    throw InvalidInput("radiation.rays_per_face must be >= 1 (got " + std::to_string(settings.rays_per_face) + ")");
  if (settings.min_rays_per_node < 0)
    throw InvalidInput("radiation.min_rays_per_node must be >= 0 (got " + std::to_string(settings.min_rays_per_node) + ")");
  // The statistical error of a node's couplings falls with its total rays: a 6-face node at
  // a fixed rays_per_face is ~30x noisier (in variance) than a 200-face one. Topping small
  // nodes up to a common total costs little (few faces) and evens the error out.
  return rays_per_side_of_node(sides, settings.rays_per_face, settings.min_rays_per_node, sides.ir_boost);
}

namespace detail {
FaceViewFactors trace_all(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings,
                          std::vector<tracing::RayRecord>* records, std::vector<std::int64_t>* record_begin) {
  if (sides.front_side.size() != scene.mesh().num_faces())
    throw InvalidInput("face_view_factors: the surface sides do not belong to the scene's mesh");
  const int S = sides.size();
  const Eigen::VectorXi rays = side_ray_counts(sides, settings);
  const auto sobol_table = tracing::shared_sobol_table(S ? rays.maxCoeff() : 0);
  const tracing::SobolTable& sobol = *sobol_table;
  std::vector<std::int64_t> begin = record_offsets(rays);
  if (records) records->resize(begin.back());
  const tracing::PrimTable prims = tracing::prim_table(scene.impl(), sides);
  SideRows rows(S);
  tbb::enumerable_thread_specific<tracing::Counter> counters([S] { return tracing::Counter(S); });
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 8), [&](const tbb::blocked_range<int>& r) {
    tracing::Counter& c = counters.local();
    for (int s = r.begin(); s != r.end(); ++s) {
      const sampling::Emitter e = tracing::side_emitter(scene.mesh(), sides, s, settings.seed);
      std::int64_t back = 0;
      tracing::RayRecord* rec = records ? records->data() + begin[s] : nullptr;
      tracing::trace_emitter(scene.impl(), prims, e, sobol, rays[s], tracing::AllRays{}, [&](int i, int hit, bool back_hit, float t) {
        c.add(hit, 1);
        back += back_hit;
        if (rec) rec[i] = tracing::RayRecord::of(hit, back_hit, t);
      });
      rows.take(s, c, back);
    }
  });
  if (record_begin) *record_begin = std::move(begin);
  return assemble(sides, rows, settings.rays_per_face, rays);
}
}  // namespace detail

FaceViewFactors face_view_factors(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings) {
  return detail::trace_all(scene, sides, settings, nullptr, nullptr);
}

FaceViewFactors face_view_factors(const RayScene& scene, const RadiationSettings& settings) {
  return face_view_factors(scene, surface_sides(scene.mesh()), settings);
}

}  // namespace thermodec
