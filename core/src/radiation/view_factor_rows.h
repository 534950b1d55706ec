#pragma once
// Private to core/src/radiation: per-side integer hit counts, gathered by any thread and
// assembled in side order (so results do not depend on scheduling).
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/rays/tracing.h"

namespace thermodec::detail {

struct SideRows {
  std::vector<std::vector<std::pair<int, std::int32_t>>> hits;  // (side, count), sorted by side
  std::vector<std::int32_t> space;
  std::vector<std::int64_t> back_hits;
  explicit SideRows(int n) : hits(n), space(n, 0), back_hits(n, 0) {}

  //! Moves the counter's content into row s and clears the counter. Returns the count left in
  //! the "gone" bucket (0 unless the incremental bookkeeping failed).
  std::int32_t take(int s, tracing::Counter& c, std::int64_t back) {
    std::sort(c.touched.begin(), c.touched.end());
    c.touched.erase(std::unique(c.touched.begin(), c.touched.end()), c.touched.end());
    auto& row = hits[s];
    row.clear();
    space[s] = 0;
    std::int32_t gone = 0;
    for (int idx : c.touched) {
      const std::int32_t n = c.count[idx];
      c.count[idx] = 0;
      if (idx == c.space()) space[s] = n;
      else if (idx == c.gone()) gone = n;
      else if (n != 0) row.emplace_back(idx, n);
    }
    c.touched.clear();
    back_hits[s] = back;
    return gone;
  }
};

//! Start of each side's rays in a side-major array of all rays (#S + 1, last = total).
inline std::vector<std::int64_t> record_offsets(const Eigen::VectorXi& rays) {
  std::vector<std::int64_t> begin(rays.size() + 1, 0);
  for (Eigen::Index s = 0; s < rays.size(); ++s) begin[s + 1] = begin[s] + rays[s];
  return begin;
}

//! `rays` = #S rays each side emitted, `base` = RadiationSettings::rays_per_face.
inline FaceViewFactors assemble(const SurfaceSides& sides, const SideRows& rows, int base, const Eigen::VectorXi& rays) {
  const int S = sides.size();
  FaceViewFactors vf;
  vf.sides = sides;
  vf.rays_per_side = base;
  vf.side_rays = rays;
  vf.rays_traced = rays.cast<std::int64_t>().sum();
  vf.F.resize(S, S);
  Eigen::VectorXi nnz(S);
  for (int s = 0; s < S; ++s) nnz[s] = static_cast<int>(rows.hits[s].size());
  vf.F.reserve(nnz);
  vf.to_space.resize(S);
  vf.back_hits_per_side.resize(S);
  for (int s = 0; s < S; ++s) {
    const double inv = 1.0 / rays[s];
    for (const auto& [t, n] : rows.hits[s]) vf.F.insert(s, t) = n * inv;
    vf.to_space[s] = rows.space[s] * inv;
    vf.back_hits_on_one_sided += rows.back_hits[s];
    vf.back_hits_per_side[s] = static_cast<int>(rows.back_hits[s]);
  }
  vf.F.makeCompressed();
  return vf;
}

//! All rays of all sides (the full computation); `records`, if non-null, receives every ray's
//! hit, in side-major ray order, side s starting at (*record_begin)[s] (record_offsets).
FaceViewFactors trace_all(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings,
                          std::vector<tracing::RayRecord>* records, std::vector<std::int64_t>* record_begin);

}  // namespace thermodec::detail
