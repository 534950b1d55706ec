#include "thermodec/radiation/radiative_couplings.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "thermodec/common/errors.h"
#include "thermodec/rays/ray_scene.h"

namespace thermodec {
namespace {

// Combines two estimates of the same quantity (A_i F_ij and A_j F_ji, or GR_ij and GR_ji) by
// inverse-variance weighting: the better-sampled direction dominates. Returns the combined
// variance; `asym_sigma` gets |x1 - x2| / sqrt(v1 + v2).
double combine(double x1, double v1, double x2, double v2, double& x, double& asym_sigma) {
  const double vs = v1 + v2;
  if (vs <= 0.0) {
    x = 0.5 * (x1 + x2);
    asym_sigma = 0.0;
    return 0.0;
  }
  x = (x1 * v2 + x2 * v1) / vs;
  asym_sigma = std::abs(x1 - x2) / std::sqrt(vs);
  return v1 * v2 / vs;
}

// Pairs whose two directions disagree beyond any noise (1 = i, j), in units of a binomial
// standard error that does not rest on either direction's own count: an exchange
// x = (X_ij + X_ji) / 2 [m^2] spread over node i's sides scores about x a_i in variance from
// i's rays, a_i = sum_s A_s^2 / R_s / sum_s A_s its area per ray [m^2] (and likewise from j's).
// Geometry makes such pairs: a face inside a closed part of another body sends rays out through
// one-sided backs that nothing outside sends back. Their inverse-variance combination takes the
// zero count as exact and weighs it against the other direction by the "one ray" floors, i.e.
// by the two nodes' ray counts: it moves with any change of ray allocation (a merged partner, a
// sampling boost, a decimated face). Reported (CouplingDiagnostics::non_reciprocal_pairs), not
// corrected: no count-free rule tried kept both Juno's and NPP_16's merges consistent
// (docs/radiation.md, Reciprocity).
Eigen::MatrixXi non_reciprocal_pairs(const FaceViewFactors& vf, const Eigen::VectorXi& group, const Eigen::MatrixXd& X,
                                     const Eigen::VectorXd& floor_vf, int N) {
  const SurfaceSides& sd = vf.sides;
  Eigen::VectorXd a2r = Eigen::VectorXd::Zero(N), area = Eigen::VectorXd::Zero(N);
  for (int s = 0; s < sd.size(); ++s) {
    const int i = group[s];
    if (i < 0 || i >= N) continue;
    const double R = vf.side_rays.size() ? vf.side_rays[s] : vf.rays_per_side;
    a2r[i] += sd.area_m2[s] * sd.area_m2[s] / R;
    area[i] += sd.area_m2[s];
  }
  Eigen::MatrixXi out = Eigen::MatrixXi::Zero(N, N);
  for (int i = 0; i < N; ++i)
    for (int j = i + 1; j < N; ++j) {
      if (!(area[i] > 0.0) || !(area[j] > 0.0)) continue;
      const double x = 0.5 * (X(i, j) + X(j, i));
      const double var = x * (a2r[i] / area[i] + a2r[j] / area[j]) + floor_vf[i] + floor_vf[j];
      if (var > 0.0 && std::abs(X(i, j) - X(j, i)) > kNonReciprocalSigma * std::sqrt(var)) out(i, j) = out(j, i) = 1;
    }
  return out;
}

// Delta-method variance of one linear combination of row i's Gebhart couplings per node i,
// sum_j M(i, j) GR_ij (columns: nodes, unassigned, space): a ray of side s landing on side t
// scores Y(t, :) M(i, :)^T (an escaping ray M(i, space)); side s's per-ray variance of that
// score, weighted by W(s, i) = A_s^2 Y(s, i)^2 (the adjoint, as for VG) and divided by its ray
// count, summed over the sides [m^4].
Eigen::VectorXd row_combination_variance(const FaceViewFactors& vf, const RowMatrixXd& Y, const RowMatrixXd& B,
                                         const Eigen::MatrixXd& W, const Eigen::MatrixXd& M) {
  const int S = vf.sides.size(), N = static_cast<int>(M.rows()), SP = N + 1;
  auto rays_of = [&](int s) -> double { return vf.side_rays.size() ? vf.side_rays[s] : vf.rays_per_side; };
  const RowMatrixXd Z = Y * M.transpose();  // S x N: the score of a ray landing on t, per node's combination
  const RowMatrixXd mean = B * M.transpose();
  RowMatrixXd V(S, N);
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 64), [&](const tbb::blocked_range<int>& r) {
    for (int s = r.begin(); s != r.end(); ++s) {
      auto v = V.row(s);
      v.setZero();
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, s); it; ++it)
        v.noalias() += it.value() * Z.row(it.col()).cwiseAbs2();
      v.noalias() += vf.to_space[s] * M.col(SP).transpose().cwiseAbs2();
      v = (v - mean.row(s).cwiseAbs2()).cwiseMax(0.0) / rays_of(s);
    }
  });
  Eigen::VectorXd out(N);
  for (int i = 0; i < N; ++i) out[i] = W.col(i).dot(V.col(i));
  return out;
}

// Symmetrising replaced each off-diagonal GR_ij of row i by the inverse-variance mean
// lambda_ij GR_ij + (1 - lambda_ij) GR_ji, which moved the row sum by
// missing_i = sum_j (1 - lambda_ij) (GR_ij - GR_ji). Every ray is counted once, so the raw row
// closes exactly (A_i eps_i = sum_j GR_ij + GR_ii + GR_i,space + GR_i,unassigned) and its
// errors sum to zero: the two entries without a second estimate, GR_i,space and GR_ii, carry
// minus the other entries' errors. They get the missing amount back in the share of the best
// linear predictor of the space error from their sum's error, w = Cov(e_space, e_space + e_ii)
// / Var(e_space + e_ii) (per-ray score covariances, delta method): the symmetrised
// off-diagonal estimates then also sharpen the coupling to space (a flat node, GR_ii = 0, takes
// it wholly from closure). GR_i,space + w missing_i is a linear combination of the raw
// estimates, so its variance follows from the same delta method: row i's part
// (row_combination_variance) plus w^2 sum_j (1 - lambda_ij)^2 Var(GR_ji) from the partners.
// `lambda`: lambda_ij, the weight of row i's own estimate; `v_partner`(j, i): Var(GR_ji) with
// its floor, as combined.
void restore_closure(const FaceViewFactors& vf, const RowMatrixXd& Y, const RowMatrixXd& B, const Eigen::MatrixXd& W,
                     const Eigen::MatrixXd& VG, const Eigen::MatrixXd& GR, const Eigen::VectorXd& emit,
                     const Eigen::MatrixXd& lambda, const Eigen::MatrixXd& v_partner, NodeCouplings& nc) {
  const int N = static_cast<int>(emit.size()), U = N, SP = N + 1, C = N + 2;
  CouplingDiagnostics& dg = nc.diagnostics;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(N, C);
  for (int i = 0; i < N; ++i) M(i, i) = M(i, SP) = 1.0;
  const Eigen::VectorXd v_sum = row_combination_variance(vf, Y, B, W, M);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(N);
  for (int i = 0; i < N; ++i) {
    const double cov = 0.5 * (v_sum[i] + VG(i, SP) - VG(i, i));
    // A node none of whose rays reached space (enclosed) keeps no coupling to it.
    if (emit[i] > 0.0 && v_sum[i] > 0.0 && GR(i, SP) > 0.0) w[i] = std::clamp(cov / v_sum[i], 0.0, 1.0);
  }
  // The corrected coupling to space: GR_i,space + w_i sum_j (1 - lambda_ij) (GR_ij - GR_ji).
  M.setZero();
  for (int i = 0; i < N; ++i) {
    M(i, SP) = 1.0;
    for (int j = 0; j < N; ++j)
      if (j != i) M(i, j) = w[i] * (1.0 - lambda(i, j));
  }
  const Eigen::VectorXd v_row = row_combination_variance(vf, Y, B, W, M);
  for (int i = 0; i < N; ++i) {
    if (!(emit[i] > 0.0)) continue;
    const double missing = emit[i] - (nc.radiative_couplings_m2.row(i).sum() + GR(i, SP) + GR(i, U));
    dg.coupling_closure_error = std::max(dg.coupling_closure_error, std::abs(missing) / emit[i]);
    double v_other = 0.0;
    for (int j = 0; j < N; ++j)
      if (j != i) v_other += std::pow(M(i, j), 2) * v_partner(j, i);
    const double sp = std::max(0.0, GR(i, SP) + w[i] * missing);
    nc.radiative_couplings_m2(i, i) = std::max(0.0, nc.radiative_couplings_m2(i, i) + missing - (sp - GR(i, SP)));
    nc.to_space_couplings_m2[i] = sp;
    nc.to_space_couplings_standard_error[i] = std::sqrt(v_row[i] + v_other);
  }
}

}  // namespace

NodeCouplings aggregate_couplings(const FaceViewFactors& vf, const Eigen::VectorXd& emissivity,
                                  const GebhartFactors& gebhart, int num_nodes) {
  const int S = vf.sides.size(), N = num_nodes;
  const int U = N, SP = N + 1, C = N + 2;  // columns: nodes, unassigned, space
  if (emissivity.size() != S) throw InvalidInput("aggregate_couplings: emissivity must have one value per side");
  if (gebhart.B.rows() != S || gebhart.B.cols() != C)
    throw InvalidInput("aggregate_couplings: Gebhart factors must be solved with node_groups(sides, " +
                       std::to_string(N) + ") and " + std::to_string(N + 1) + " groups");
  if (vf.side_rays.size() != 0 && vf.side_rays.size() != S)
    throw InvalidInput("aggregate_couplings: side_rays must have one count per side");
  // Rays emitted by side s (sides of small nodes emit more, see side_ray_counts).
  auto rays_of = [&](int s) -> double { return vf.side_rays.size() ? vf.side_rays[s] : vf.rays_per_side; };
  const SurfaceSides& sd = vf.sides;
  const Eigen::VectorXi group = node_groups(sd, N);
  const Eigen::VectorXd& A = sd.area_m2;
  const Eigen::VectorXd rho = (1.0 - emissivity.array()).matrix();

  NodeCouplings nc;
  CouplingDiagnostics& dg = nc.diagnostics;
  dg.rays_traced = vf.rays_traced;
  dg.back_hits_on_one_sided = vf.back_hits_on_one_sided;
  dg.surface_sides = S;
  dg.gebhart_iterations = gebhart.iterations;
  dg.gebhart_closure_error = gebhart.max_closure_error;

  // ---- view factors: X_ij = sum_{s in i} A_s F_s->j, binomial variance per side ----------
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(N, C), VX = Eigen::MatrixXd::Zero(N, C);
  Eigen::VectorXd area = Eigen::VectorXd::Zero(N), floor_vf = Eigen::VectorXd::Zero(N);
  Eigen::VectorXd row(C);
  for (int s = 0; s < S; ++s) {  // sequential: fixed summation order
    const int i = group[s];
    if (i == U) {
      dg.unassigned_area_m2 += A[s];
      continue;
    }
    area[i] += A[s];
    const double R = rays_of(s);
    floor_vf[i] += A[s] * A[s] / (R * R);  // "one ray" resolution: no estimate is exact
    row.setZero();
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, s); it; ++it) row[group[it.col()]] += it.value();
    row[SP] = vf.to_space[s];
    for (int j = 0; j < C; ++j)
      if (row[j] != 0.0) {
        X(i, j) += A[s] * row[j];
        VX(i, j) += A[s] * A[s] * row[j] * (1.0 - row[j]) / R;
      }
  }
  nc.area_m2 = area;
  const Eigen::MatrixXi broken = non_reciprocal_pairs(vf, group, X, floor_vf, N);
  nc.view_factors.setZero(N, N);
  nc.view_factors_standard_error.setZero(N, N);
  nc.to_space.setZero(N);
  nc.to_space_standard_error.setZero(N);
  for (int i = 0; i < N; ++i) {
    if (area[i] <= 0.0) continue;
    for (int j = i; j < N; ++j) {
      if (area[j] <= 0.0) continue;
      double x, v, sig = 0.0;
      if (i == j) {
        x = X(i, i);
        v = VX(i, i);
      } else {
        dg.non_reciprocal_pairs += broken(i, j);
        v = combine(X(i, j), VX(i, j) + floor_vf[i], X(j, i), VX(j, i) + floor_vf[j], x, sig);
        dg.view_factor_asymmetry_sigma = std::max(dg.view_factor_asymmetry_sigma, sig);
      }
      nc.view_factors(i, j) = x / area[i];
      nc.view_factors(j, i) = x / area[j];
      nc.view_factors_standard_error(i, j) = std::sqrt(v) / area[i];
      nc.view_factors_standard_error(j, i) = std::sqrt(v) / area[j];
    }
    nc.to_space[i] = X(i, SP) / area[i];
    nc.to_space_standard_error[i] = std::sqrt(VX(i, SP)) / area[i];
    const double closure = nc.view_factors.row(i).sum() + nc.to_space[i] + X(i, U) / area[i] - 1.0;
    dg.view_factor_closure_error = std::max(dg.view_factor_closure_error, std::abs(closure));
  }

  // ---- Gebhart couplings -----------------------------------------------------------------
  // Y(t, j) = eps_t [t in j] + rho_t B(t, j): the value a ray scores for group j when it lands
  // on side t (space scores 1 for the space column). The per-ray variance of side s for j is
  // sum_t F_st Y(t, j)^2 + [j = space] F_s,space - B(s, j)^2, and a perturbation of side s's
  // rays moves GR_ij by A_s Y(s, i) times it (the adjoint of the Gebhart system, which by
  // reciprocity is Y itself): Var(GR_ij) = sum_s A_s^2 Y(s, i)^2 V(s, j) / R (delta method).
  const RowMatrixXd& B = gebhart.B;
  RowMatrixXd Y = rho.asDiagonal() * B;
  for (int t = 0; t < S; ++t) Y(t, group[t]) += emissivity[t];
  RowMatrixXd V(S, C);
  Eigen::RowVectorXd space_score = Eigen::RowVectorXd::Zero(C);  // an escaping ray scores 1 for space
  space_score[SP] = 1.0;
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 64), [&](const tbb::blocked_range<int>& r) {
    for (int s = r.begin(); s != r.end(); ++s) {
      auto v = V.row(s);
      v.setZero();
      if (!vf.controlled.empty() && vf.controlled[s].strata.count > 0) {
        // a regression estimate (planar control variates): what the crossings leave
        v = controlled_score_variance(vf.controlled[s], Y, space_score) / rays_of(s);
        continue;
      }
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, s); it; ++it)
        v.noalias() += it.value() * Y.row(it.col()).cwiseAbs2();
      v[SP] += vf.to_space[s];
      v = (v - B.row(s).cwiseAbs2()).cwiseMax(0.0) / rays_of(s);
    }
  });
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(S, N);  // W(s, i) = A_s^2 Y(s, i)^2
  for (int s = 0; s < S; ++s)
    for (int i = 0; i < N; ++i) W(s, i) = A[s] * A[s] * Y(s, i) * Y(s, i);
  const Eigen::MatrixXd VG = W.transpose() * V;  // N x C (V already per side's ray count)
  Eigen::MatrixXd GR = Eigen::MatrixXd::Zero(N, C);
  Eigen::VectorXd emit = Eigen::VectorXd::Zero(N), floor_gr = Eigen::VectorXd::Zero(N);
  for (int s = 0; s < S; ++s) {
    const int i = group[s];
    if (i == U) continue;
    GR.row(i) += (A[s] * emissivity[s]) * B.row(s);
    emit[i] += A[s] * emissivity[s];
    const double R = rays_of(s);
    floor_gr[i] += (A[s] * emissivity[s]) * (A[s] * emissivity[s]) / (R * R);
  }
  const Eigen::VectorXd ymax = Y.colwise().maxCoeff().transpose();
  nc.radiative_couplings_m2.setZero(N, N);
  nc.radiative_couplings_standard_error.setZero(N, N);
  nc.to_space_couplings_m2.setZero(N);
  nc.to_space_couplings_standard_error.setZero(N);
  const double gr_max = N ? GR.leftCols(N).maxCoeff() : 0.0;
  Eigen::MatrixXd lambda = Eigen::MatrixXd::Ones(N, N), v_dir = Eigen::MatrixXd::Zero(N, N);
  for (int i = 0; i < N; ++i) {
    for (int j = i; j < N; ++j) {
      double x, v, sig = 0.0;
      if (i == j) {
        x = GR(i, i);
        v = VG(i, i);
      } else {
        v_dir(i, j) = VG(i, j) + floor_gr[i] * ymax[j] * ymax[j];
        v_dir(j, i) = VG(j, i) + floor_gr[j] * ymax[i] * ymax[i];
        v = combine(GR(i, j), v_dir(i, j), GR(j, i), v_dir(j, i), x, sig);
        const double vs = v_dir(i, j) + v_dir(j, i);
        lambda(i, j) = vs > 0.0 ? v_dir(j, i) / vs : 0.5;
        lambda(j, i) = 1.0 - lambda(i, j);
        dg.coupling_asymmetry_sigma = std::max(dg.coupling_asymmetry_sigma, sig);
        const double big = std::max(GR(i, j), GR(j, i));
        if (big > 1e-3 * gr_max && big > 0.0)
          dg.coupling_asymmetry_relative = std::max(dg.coupling_asymmetry_relative, std::abs(GR(i, j) - GR(j, i)) / big);
      }
      nc.radiative_couplings_m2(i, j) = nc.radiative_couplings_m2(j, i) = x;
      nc.radiative_couplings_standard_error(i, j) = nc.radiative_couplings_standard_error(j, i) = std::sqrt(v);
    }
    nc.to_space_couplings_m2[i] = GR(i, SP);
    nc.to_space_couplings_standard_error[i] = std::sqrt(VG(i, SP));
  }
  restore_closure(vf, Y, B, W, VG, GR, emit, lambda, v_dir, nc);
  return nc;
}

NodeCouplings radiative_couplings(const ThermalModel& model, const RadiationSettings& settings) {
  const int N = static_cast<int>(model.nodes.size());
  RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  const FaceViewFactors vf = face_view_factors(scene, sides, settings);
  const Eigen::VectorXd eps = side_emissivity(model, sides);
  const GebhartFactors gb = gebhart_factors(vf, eps, node_groups(sides, N), N + 1);
  NodeCouplings nc = aggregate_couplings(vf, eps, gb, N);
  nc.diagnostics.untraceable_faces = scene.num_skipped_faces();
  return nc;
}

}  // namespace thermodec
