// Reciprocity-enforced side-to-side view factors (see the header).
//
// A_s F_st and A_t F_ts estimate the same exchange area from the rays of s and of t. With ray
// densities d_s = N_s / A_s, the estimates' variances are ~ A_s G / N_s = G / d_s and G / d_t
// (binomial, small F), so the inverse-variance mean is G' = (d_s A_s F_st + d_t A_t F_ts) /
// (d_s + d_t) = (N_s F_st + N_t F_ts) / (d_s + d_t). Scrambled Sobol rays converge faster than
// the binomial rate, but alike at both ends, so the weights keep their ratio.
#include "thermodec/radiation/reciprocal_view_factors.h"

#include <Eigen/SparseCore>
#include <vector>

namespace thermodec {

FaceViewFactors reciprocal_view_factors(const FaceViewFactors& vf) {
  FaceViewFactors out = vf;
  const int S = vf.sides.size();
  if (S == 0 || vf.F.rows() != S || vf.F.cols() != S || vf.to_space.size() != S) return out;
  const Eigen::VectorXd& A = vf.sides.area_m2;
  auto rays_of = [&](int s) -> double { return vf.side_rays.size() == S ? vf.side_rays[s] : vf.rays_per_side; };
  auto usable = [&](int s) { return A[s] > 0.0 && rays_of(s) > 0.0; };
  // Row s of Ft: F(t, s) over the emitting sides t, in column order as F's rows.
  const Eigen::SparseMatrix<double, Eigen::RowMajor> Ft = Eigen::SparseMatrix<double, Eigen::RowMajor>(vf.F.transpose());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(vf.F.nonZeros()) * 2);
  std::vector<std::pair<int, double>> row;
  for (int s = 0; s < S; ++s) {  // sequential: a fixed summation order
    row.clear();
    double before = 0.0, after = 0.0;
    Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator a(vf.F, s), b(Ft, s);
    while (a || b) {  // merge of the two sorted index lists
      const int t = a && (!b || a.col() <= b.col()) ? static_cast<int>(a.col()) : static_cast<int>(b.col());
      const double f_st = a && a.col() == t ? a.value() : 0.0, f_ts = b && b.col() == t ? b.value() : 0.0;
      if (a && a.col() == t) ++a;
      if (b && b.col() == t) ++b;
      before += f_st;
      double f = f_st;
      if (t != s && usable(s) && usable(t)) {
        const double ds = rays_of(s) / A[s], dt = rays_of(t) / A[t];
        f = (rays_of(s) * f_st + rays_of(t) * f_ts) / (ds + dt) / A[s];
      }
      if (f != 0.0) row.emplace_back(t, f);
      after += f;
    }
    double space = vf.to_space[s] + before - after;
    const double scale = after > 0.0 && after > before + vf.to_space[s] ? (before + vf.to_space[s]) / after : 1.0;
    if (scale < 1.0) space = 0.0;
    for (const auto& [t, f] : row) entries.emplace_back(s, t, f * scale);
    out.to_space[s] = space < 0.0 ? 0.0 : space;
  }
  out.F.setZero();
  out.F.setFromTriplets(entries.begin(), entries.end());
  out.F.makeCompressed();
  return out;
}

}  // namespace thermodec
