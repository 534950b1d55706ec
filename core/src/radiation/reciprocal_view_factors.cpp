// Reciprocity-enforced side-to-side view factors (see the header).
//
// A_s F_st and A_t F_ts estimate the same exchange area from the rays of s and of t. With ray
// densities d_s = N_s / A_s, the estimates' variances are ~ A_s G / N_s = G / d_s and G / d_t
// (binomial, small F), so the inverse-variance mean is G' = (d_s A_s F_st + d_t A_t F_ts) /
// (d_s + d_t) = (N_s F_st + N_t F_ts) / (d_s + d_t). Scrambled Sobol rays converge faster than
// the binomial rate, but alike at both ends, so the weights keep their ratio.
//
// Memory: F can be the largest object of a run (1.4 GB on a 100k-face model), so no transpose
// is formed: F_ts is found in row t by a cursor that a block of rows s, read in order, moves
// forwards (EntryLookup), and only the pairs seen from t alone (rarely many) are collected
// apart. The result is built in place of the copy's F.
#include "thermodec/radiation/reciprocal_view_factors.h"

#include <Eigen/SparseCore>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <tuple>
#include <vector>

namespace thermodec {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// F(s, t), 0 if absent (rows of a compressed row-major matrix hold sorted column indices),
// for a run of look-ups whose columns t never decrease (one block of rows, in order): each row
// s keeps a cursor, placed by a binary search at its first look-up in the run and moved on
// from there, so a run costs about one search per row it reads, not one per look-up. The
// cursor stops where the search would (the first column >= t): the same entry.
class EntryLookup {
 public:
  explicit EntryLookup(int rows) : cursor_(rows, 0), run_of_(rows, -1) {}
  void start_run(int run) { run_ = run; }
  double operator()(const RowSparse& F, int s, int t) {
    const int* cols = F.innerIndexPtr();
    const int end = F.outerIndexPtr()[s + 1];
    int& k = cursor_[s];
    if (run_of_[s] != run_) {
      run_of_[s] = run_;
      k = static_cast<int>(std::lower_bound(cols + F.outerIndexPtr()[s], cols + end, t) - cols);
    } else {
      while (k < end && cols[k] < t) ++k;
    }
    return k != end && cols[k] == t ? F.valuePtr()[k] : 0.0;
  }

 private:
  std::vector<int> cursor_, run_of_;
  int run_ = -1;
};

}  // namespace

FaceViewFactors reciprocal_view_factors(const FaceViewFactors& vf) {
  const int S = vf.sides.size();
  FaceViewFactors out;
  out.sides = vf.sides;
  out.to_space = vf.to_space;
  out.rays_per_side = vf.rays_per_side;
  out.side_rays = vf.side_rays;
  out.rays_traced = vf.rays_traced;
  out.back_hits_on_one_sided = vf.back_hits_on_one_sided;
  out.back_hits_per_side = vf.back_hits_per_side;
  if (S == 0 || vf.F.rows() != S || vf.F.cols() != S || vf.to_space.size() != S) {
    out.F = vf.F;
    return out;
  }
  RowSparse compressed;  // (only if vf.F is not: the binary search needs sorted, packed rows)
  if (!vf.F.isCompressed()) {
    compressed = vf.F;
    compressed.makeCompressed();
  }
  const RowSparse& F = vf.F.isCompressed() ? vf.F : compressed;
  const Eigen::VectorXd& A = vf.sides.area_m2;
  auto rays_of = [&](int s) -> double { return vf.side_rays.size() == S ? vf.side_rays[s] : vf.rays_per_side; };
  auto usable = [&](int s) { return A[s] > 0.0 && rays_of(s) > 0.0; };
  // Pairs (s, t) with F_ts > 0 but no F_st: (s, t, F_ts), sorted by row s then t (unique
  // pairs: one order whatever the threads found them in).
  tbb::enumerable_thread_specific<std::vector<std::tuple<int, int, double>>> found;
  tbb::enumerable_thread_specific<EntryLookup> lookups([S] { return EntryLookup(S); });
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 256), [&](const tbb::blocked_range<int>& r) {
    auto& mine = found.local();
    EntryLookup& entry = lookups.local();
    entry.start_run(r.begin());
    for (int t = r.begin(); t != r.end(); ++t)
      for (RowSparse::InnerIterator it(F, t); it; ++it) {
        const int s = static_cast<int>(it.col());
        if (s != t && it.value() != 0.0 && usable(s) && usable(t) && entry(F, s, t) == 0.0)
          mine.emplace_back(s, t, it.value());
      }
  });
  // Sorted by row s then t (the pairs are unique): counted into rows, then each row's few
  // pairs sorted by t.
  std::vector<std::size_t> seen_begin(S + 1, 0);  // row s's pairs: [seen_begin[s], seen_begin[s + 1])
  for (const auto& v : found)
    for (const auto& p : v) ++seen_begin[std::get<0>(p) + 1];
  for (int s = 0; s < S; ++s) seen_begin[s + 1] += seen_begin[s];
  std::vector<std::tuple<int, int, double>> seen_from_t(seen_begin[S]);
  {
    std::vector<std::size_t> next(seen_begin.begin(), seen_begin.end() - 1);
    for (const auto& v : found)
      for (const auto& p : v) seen_from_t[next[std::get<0>(p)]++] = p;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 1024), [&](const tbb::blocked_range<int>& r) {
    for (int s = r.begin(); s != r.end(); ++s)
      std::sort(seen_from_t.begin() + static_cast<std::ptrdiff_t>(seen_begin[s]),
                seen_from_t.begin() + static_cast<std::ptrdiff_t>(seen_begin[s + 1]));
  });
  // Rows are independent (each sums its own entries in column order): laid out first, then
  // filled in parallel, each by the same sequence of operations as one row after another.
  RowSparse G(S, S);
  G.makeCompressed();
  G.resizeNonZeros(F.nonZeros() + static_cast<Eigen::Index>(seen_from_t.size()));
  int* outer = G.outerIndexPtr();
  outer[0] = 0;
  for (int s = 0; s < S; ++s)
    outer[s + 1] = outer[s] + (F.outerIndexPtr()[s + 1] - F.outerIndexPtr()[s]) +
                   static_cast<int>(seen_begin[s + 1] - seen_begin[s]);
  int* inner = G.innerIndexPtr();
  double* value = G.valuePtr();
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 64), [&](const tbb::blocked_range<int>& r) {
    EntryLookup& entry = lookups.local();
    entry.start_run(S + r.begin());  // (the runs above were numbered 0 .. S - 1)
    for (int s = r.begin(); s != r.end(); ++s) {
      double before = 0.0, after = 0.0;
      int k = outer[s];
      auto add = [&](int t, double f_st, double f_ts) {
        before += f_st;
        double f = f_st;
        if (t != s && usable(s) && usable(t)) {
          const double ds = rays_of(s) / A[s], dt = rays_of(t) / A[t];
          f = (rays_of(s) * f_st + rays_of(t) * f_ts) / (ds + dt) / A[s];
        }
        after += f;
        inner[k] = t;
        value[k++] = f;
      };
      RowSparse::InnerIterator it(F, s);
      std::size_t next = seen_begin[s];
      while (it || next < seen_begin[s + 1]) {  // merge, column order
        const bool from_t = next < seen_begin[s + 1] && (!it || std::get<1>(seen_from_t[next]) < it.col());
        if (from_t) {
          add(std::get<1>(seen_from_t[next]), 0.0, std::get<2>(seen_from_t[next]));
          ++next;
        } else {
          const int t = static_cast<int>(it.col());
          add(t, it.value(), t == s ? 0.0 : entry(F, t, s));
          ++it;
        }
      }
      const double total = before + vf.to_space[s];
      if (after > total && after > 0.0) {  // scaled back to a closed row, nothing escapes
        for (int j = outer[s]; j < outer[s + 1]; ++j) value[j] *= total / after;
        out.to_space[s] = 0.0;
      } else {
        out.to_space[s] = total - after;
      }
    }
  });
  out.F = std::move(G);
  return out;
}

}  // namespace thermodec
