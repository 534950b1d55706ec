#pragma once
// Private to core/src/radiation: per-side integer hit counts, gathered by any thread and
// assembled in side order (so results do not depend on scheduling).
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "thermodec/radiation/face_view_factors.h"
#include "tracing.h"

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

inline FaceViewFactors assemble(const SurfaceSides& sides, const SideRows& rows, int R) {
  const int S = sides.size();
  FaceViewFactors vf;
  vf.sides = sides;
  vf.rays_per_side = R;
  vf.rays_traced = std::int64_t(S) * R;
  vf.F.resize(S, S);
  Eigen::VectorXi nnz(S);
  for (int s = 0; s < S; ++s) nnz[s] = static_cast<int>(rows.hits[s].size());
  vf.F.reserve(nnz);
  vf.to_space.resize(S);
  vf.back_hits_per_side.resize(S);
  const double inv = 1.0 / R;
  for (int s = 0; s < S; ++s) {
    for (const auto& [t, n] : rows.hits[s]) vf.F.insert(s, t) = n * inv;
    vf.to_space[s] = rows.space[s] * inv;
    vf.back_hits_on_one_sided += rows.back_hits[s];
    vf.back_hits_per_side[s] = static_cast<int>(rows.back_hits[s]);
  }
  vf.F.makeCompressed();
  return vf;
}

//! All rays of all sides (the full computation); `records`, if non-null, is resized to
//! #S x R and receives every ray's hit, in side-major ray order.
FaceViewFactors trace_all(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings,
                          std::vector<tracing::RayRecord>* records);

}  // namespace thermodec::detail
