#include "thermodec/radiation/face_view_factors.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

#include "tracing.h"
#include "thermodec/common/errors.h"
#include "view_factor_rows.h"

namespace thermodec {

namespace detail {
FaceViewFactors trace_all(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings,
                          std::vector<tracing::RayRecord>* records) {
  if (settings.rays_per_face < 1)
    throw InvalidInput("radiation.rays_per_face must be >= 1 (got " + std::to_string(settings.rays_per_face) + ")");
  if (sides.front_side.size() != scene.mesh().num_faces())
    throw InvalidInput("face_view_factors: the surface sides do not belong to the scene's mesh");
  const int S = sides.size(), R = settings.rays_per_face;
  const tracing::SobolTable sobol = sampling::sobol_4d_reversed(R);
  if (records) records->resize(std::size_t(S) * R);
  const tracing::PrimTable prims = tracing::prim_table(scene.impl(), sides);
  SideRows rows(S);
  tbb::enumerable_thread_specific<tracing::Counter> counters([S] { return tracing::Counter(S); });
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 8), [&](const tbb::blocked_range<int>& r) {
    tracing::Counter& c = counters.local();
    for (int s = r.begin(); s != r.end(); ++s) {
      const sampling::Emitter e = tracing::side_emitter(scene.mesh(), sides, s, settings.seed);
      std::int64_t back = 0;
      tracing::RayRecord* rec = records ? records->data() + std::size_t(s) * R : nullptr;
      tracing::trace_emitter(scene.impl(), prims, e, sobol, R, tracing::AllRays{}, [&](int i, int hit, bool back_hit, float t) {
        c.add(hit, 1);
        back += back_hit;
        if (rec) rec[i] = tracing::RayRecord::of(hit, back_hit, t);
      });
      rows.take(s, c, back);
    }
  });
  return assemble(sides, rows, R);
}
}  // namespace detail

FaceViewFactors face_view_factors(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings) {
  return detail::trace_all(scene, sides, settings, nullptr);
}

FaceViewFactors face_view_factors(const RayScene& scene, const RadiationSettings& settings) {
  return face_view_factors(scene, surface_sides(scene.mesh()), settings);
}

}  // namespace thermodec
