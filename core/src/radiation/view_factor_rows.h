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
  //! Per row: fractions weighed by planar control variates (planar_strata.h) that replace
  //! `hits` / `space` when the row is weighted (`weighted[s]`), sorted by side.
  std::vector<std::vector<std::pair<int, double>>> weighted_hits;
  std::vector<double> weighted_space;
  std::vector<char> weighted;
  std::vector<ControlledSide> controlled;  //!< per side if any row is weighted
  explicit SideRows(int n)
      : hits(n), space(n, 0), back_hits(n, 0), reference_row(n, -1), weighted_hits(n), weighted_space(n, 0.0), weighted(n, 0) {}

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

  //! Row s from the counters of its strata (one per mask of crossed hulls): a count of mask k
  //! weighs weight[k] (stratum_weights); clears the counters. `cs` (the side's hulls and rays
  //! per mask) is stored in `controlled[s]` with the per-mask hits the variance needs;
  //! `controlled` must have been sized to the sides.
  void take_strata(int s, std::vector<tracing::Counter>& strata, const std::vector<double>& weight, std::int64_t back,
                   ControlledSide cs) {
    auto& row = weighted_hits[s];
    row.clear();
    double sp = 0.0;
    double R = 0.0;
    for (double n : cs.rays_per_stratum) R += n;
    cs.hits.assign(weight.size(), {});
    for (std::size_t k = 0; k < weight.size(); ++k) {
      tracing::Counter& c = strata[k];
      std::sort(c.touched.begin(), c.touched.end());
      c.touched.erase(std::unique(c.touched.begin(), c.touched.end()), c.touched.end());
      for (int idx : c.touched) {
        const std::int32_t n = c.count[idx];
        if (n == 0) continue;
        c.count[idx] = 0;
        if (idx == c.space()) sp += weight[k] * n;
        else if (idx != c.gone()) row.emplace_back(idx, weight[k] * n);
        if (idx != c.gone()) cs.hits[k].emplace_back(idx == c.space() ? -1 : idx, n / R);
      }
      c.touched.clear();
    }
    controlled[s] = std::move(cs);
    // Entries of the same side from several strata, summed in stratum order (deterministic).
    std::stable_sort(row.begin(), row.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    std::size_t w = 0;
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (w > 0 && row[w - 1].first == row[i].first) row[w - 1].second += row[i].second;
      else row[w++] = row[i];
    }
    row.resize(w);
    hits[s].clear();
    space[s] = 0;
    reference_row[s] = -1;
    weighted_space[s] = sp;
    weighted[s] = 1;
    back_hits[s] = back;
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
    if (rows.weighted[s]) {
      nnz[s] = static_cast<int>(rows.weighted_hits[s].size());
      continue;
    }
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
    if (rows.weighted[s]) {
      for (const auto& [t, x] : rows.weighted_hits[s]) vf.F.insert(s, t) = x;
      vf.to_space[s] = rows.weighted_space[s];
    } else {
      for (const auto& [t, n] : r < 0 ? rows.hits[s] : kept) vf.F.insert(s, t) = n * inv;
      vf.to_space[s] = space * inv;
    }
    vf.back_hits_on_one_sided += back;
    vf.back_hits_per_side[s] = static_cast<int>(back);
  }
  vf.F.makeCompressed();
  vf.controlled = rows.controlled;
  return vf;
}

//! All rays of all sides (the full computation); `records`, if non-null, receives every ray's
//! hit, in side-major ray order, side s starting at (*record_begin)[s] (record_offsets).
FaceViewFactors trace_all(const RayScene& scene, const SurfaceSides& sides, const RadiationSettings& settings,
                          std::vector<tracing::RayRecord>* records, std::vector<std::int64_t>* record_begin);

}  // namespace thermodec::detail
