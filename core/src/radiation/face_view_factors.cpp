#include "thermodec/radiation/face_view_factors.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

#include "thermodec/radiation/planar_strata.h"
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
  // Planar strata (simulate only: records are for a reduction's ray-by-ray updates).
  std::vector<NodeHull> hulls;
  std::vector<SideStrata> strata;
  if (settings.planar_strata && !records && S > 0) {
    hulls = planar_node_hulls(scene.mesh(), sides, sides.node.maxCoeff() + 1);
    strata = side_strata(scene.mesh(), sides, hulls);
    rows.controlled.resize(S);
  }
  tbb::enumerable_thread_specific<tracing::Counter> counters([S] { return tracing::Counter(S); });
  tbb::enumerable_thread_specific<std::vector<tracing::Counter>> stratum_counters(
      [S] { return std::vector<tracing::Counter>(1 << kMaxStrataPerSide, tracing::Counter(S)); });
  tbb::enumerable_thread_specific<std::vector<std::uint8_t>> stratum_of(std::vector<std::uint8_t>{});
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 8), [&](const tbb::blocked_range<int>& r) {
    tracing::Counter& c = counters.local();
    for (int s = r.begin(); s != r.end(); ++s) {
      const sampling::Emitter e = tracing::side_emitter(scene.mesh(), sides, s, settings.seed);
      std::int64_t back = 0;
      if (!strata.empty() && strata[s].count > 0) {
        const SideStrata& st = strata[s];
        std::vector<tracing::Counter>& cs = stratum_counters.local();
        std::vector<std::uint8_t>& which = stratum_of.local();
        which.assign(rays[s], 0);
        tracing::trace_emitter(
            scene.impl(), prims, e, sobol, rays[s],
            [&](int i, const float* o, const float* d) {
              which[i] = static_cast<std::uint8_t>(stratum_of_ray(st, hulls, o, d));
              return true;
            },
            [&](int i, int hit, bool back_hit, float) {
              cs[which[i]].add(hit, 1);
              back += back_hit;
            });
        std::vector<double> n(std::size_t(1) << st.count, 0.0);
        for (std::uint8_t k : which) n[k] += 1.0;
        const std::vector<double> w = stratum_weights(st, n);
        rows.take_strata(s, cs, w, back, ControlledSide{st, std::move(n), {}});
        continue;
      }
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
