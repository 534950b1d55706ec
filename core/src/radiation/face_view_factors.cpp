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

FaceViewFactors face_view_factors(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings) {
  if (settings.rays_per_face < 1)
    throw InvalidInput("radiation.rays_per_face must be >= 1 (got " + std::to_string(settings.rays_per_face) + ")");
  if (sides.front_side.size() != scene.mesh().num_faces())
    throw InvalidInput("face_view_factors: the surface sides do not belong to the scene's mesh");
  const int S = sides.size(), R = settings.rays_per_face;
  const tracing::SobolTable sobol = sampling::sobol_4d(R);
  detail::SideRows rows(S);
  tbb::enumerable_thread_specific<tracing::Counter> counters([S] { return tracing::Counter(S); });
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 8), [&](const tbb::blocked_range<int>& r) {
    tracing::Counter& c = counters.local();
    for (int s = r.begin(); s != r.end(); ++s) {
      const sampling::Emitter e = tracing::side_emitter(scene.mesh(), sides, s, settings.seed);
      std::int64_t back = 0;
      tracing::trace_emitter(scene.impl(), sides, e, sobol, R, nullptr, [&](int hit, bool back_hit) {
        c.add(hit, 1);
        back += back_hit;
      });
      rows.take(s, c, back);
    }
  });
  return detail::assemble(sides, rows, R);
}

FaceViewFactors face_view_factors(const RayScene& scene, const RadiationSettings& settings) {
  return face_view_factors(scene, surface_sides(scene.mesh()), settings);
}

}  // namespace thermodec
