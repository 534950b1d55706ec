#pragma once
// Private to core/src/radiation: per-side integer hit counts, gathered by any thread and
// assembled in side order (so results do not depend on scheduling).
#include <algorithm>
#include <cmath>
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
  //! Per row: the reference row it equals (a candidate side none of whose rays can meet the
  //! change), copied at assembly instead of held twice; -1: the row is in `hits`.
  std::vector<int> reference_row;
  explicit SideRows(int n) : hits(n), space(n, 0), back_hits(n, 0), reference_row(n, -1) {}

  void keep_reference(int s, int ref_side) {
    hits[s].clear();
    reference_row[s] = ref_side;
  }

  //! Moves the counter's content into row s and clears the counter. Returns the count left in
  //! the "gone" bucket (0 unless the incremental bookkeeping failed).
  std::int32_t take(int s, tracing::Counter& c, std::int64_t back) {
    std::sort(c.touched.begin(), c.touched.end());
    c.touched.erase(std::unique(c.touched.begin(), c.touched.end()), c.touched.end());
    auto& row = hits[s];
    row.clear();
    reference_row[s] = -1;
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

//! The rows a candidate keeps from its reference (SideRows::reference_row): the reference's
//! view factors and, per reference side, its candidate side.
struct ReferenceRows {
  const FaceViewFactors& vf;
  const std::vector<int>& cand_of_ref;
};

//! `rays` = #S rays each side emitted, `base` = RadiationSettings::rays_per_face; `reference`
//! is needed when some rows are kept from it.
inline FaceViewFactors assemble(const SurfaceSides& sides, const SideRows& rows, int base, const Eigen::VectorXi& rays,
                                const ReferenceRows* reference = nullptr) {
  const int S = sides.size();
  FaceViewFactors vf;
  vf.sides = sides;
  vf.rays_per_side = base;
  vf.side_rays = rays;
  vf.rays_traced = rays.cast<std::int64_t>().sum();
  vf.F.resize(S, S);
  Eigen::VectorXi nnz(S);
  for (int s = 0; s < S; ++s) {
    const int r = rows.reference_row[s];
    nnz[s] = r < 0 ? static_cast<int>(rows.hits[s].size()) : reference->vf.F.outerIndexPtr()[r + 1] - reference->vf.F.outerIndexPtr()[r];
  }
  vf.F.reserve(nnz);
  vf.to_space.resize(S);
  vf.back_hits_per_side.resize(S);
  std::vector<std::pair<int, std::int32_t>> kept;
  for (int s = 0; s < S; ++s) {
    const double inv = 1.0 / rays[s];
    const int r = rows.reference_row[s];
    std::int32_t space = rows.space[s];
    std::int64_t back = rows.back_hits[s];
    if (r >= 0) {  // the reference's counts (same rays), under the candidate's side numbers
      kept.clear();
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(reference->vf.F, r); it; ++it)
        kept.emplace_back(reference->cand_of_ref[it.col()], static_cast<std::int32_t>(std::lround(it.value() * rays[s])));
      if (!std::is_sorted(kept.begin(), kept.end())) std::sort(kept.begin(), kept.end());
      space = static_cast<std::int32_t>(std::lround(reference->vf.to_space[r] * rays[s]));
      back = reference->vf.back_hits_per_side[r];
    }
    for (const auto& [t, n] : r < 0 ? rows.hits[s] : kept) vf.F.insert(s, t) = n * inv;
    vf.to_space[s] = space * inv;
    vf.back_hits_on_one_sided += back;
    vf.back_hits_per_side[s] = static_cast<int>(back);
  }
  vf.F.makeCompressed();
  return vf;
}

//! All rays of all sides (the full computation); `records`, if non-null, receives every ray's
//! hit, in side-major ray order, side s starting at (*record_begin)[s] (record_offsets).
FaceViewFactors trace_all(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings,
                          std::vector<tracing::RayRecord>* records, std::vector<std::int64_t>* record_begin);

}  // namespace thermodec::detail
