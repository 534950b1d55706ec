#include "thermodec/radiation/gebhart_factors.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/IterativeLinearSolvers>

#include "thermodec/common/errors.h"

namespace thermodec {

Eigen::VectorXi node_groups(const SurfaceSides& sides, int num_nodes) {
  Eigen::VectorXi g(sides.size());
  for (int s = 0; s < sides.size(); ++s) g[s] = (sides.node[s] >= 0 && sides.node[s] < num_nodes) ? sides.node[s] : num_nodes;
  return g;
}

GebhartFactors gebhart_factors(const FaceViewFactors& vf, const Eigen::VectorXd& absorptivity,
                               const Eigen::VectorXi& group_of_side, int num_groups, const GebhartSettings& settings,
                               const RowMatrixXd* warm_start) {
  const int S = vf.sides.size(), G = num_groups, C = num_groups + 1;
  if (absorptivity.size() != S || group_of_side.size() != S || vf.F.rows() != S || vf.F.cols() != S ||
      vf.to_space.size() != S)
    throw InvalidInput("gebhart_factors: " + std::to_string(S) + " sides but absorptivity has " +
                       std::to_string(absorptivity.size()) + " values and group_of_side " +
                       std::to_string(group_of_side.size()));
  if (G < 1) throw InvalidInput("gebhart_factors: num_groups must be >= 1");
  for (int s = 0; s < S; ++s) {
    if (!(absorptivity[s] > 0.0 && absorptivity[s] <= 1.0))
      throw InvalidInput("gebhart_factors: absorptivity of side " + std::to_string(s) + " (face " +
                         std::to_string(vf.sides.face[s]) + ") is " + std::to_string(absorptivity[s]) +
                         ", outside (0, 1]");
    if (group_of_side[s] < 0 || group_of_side[s] >= G)
      throw InvalidInput("gebhart_factors: group of side " + std::to_string(s) + " is " +
                         std::to_string(group_of_side[s]) + ", outside [0, " + std::to_string(G) + ")");
  }
  if (warm_start && (warm_start->rows() != S || warm_start->cols() != C))
    throw InvalidInput("gebhart_factors: warm start must be " + std::to_string(S) + " x " + std::to_string(C));

  const Eigen::VectorXd rho = (1.0 - absorptivity.array()).matrix();
  // Direct term E(s, g) = sum_t F(s, t) a_t [t in g]; space column = F(s, space).
  RowMatrixXd E = RowMatrixXd::Zero(S, C);
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 64), [&](const tbb::blocked_range<int>& r) {
    for (int s = r.begin(); s != r.end(); ++s) {
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, s); it; ++it)
        E(s, group_of_side[it.col()]) += it.value() * absorptivity[it.col()];
      E(s, G) = vf.to_space[s];
    }
  });

  GebhartFactors out;
  RowMatrixXd X = warm_start ? *warm_start : E;
  if (warm_start) {
    // Rows the warm start leaves at zero (no solution row is: each sums to 1) are a reduction
    // trial's new sides. Two in-place passes over just them, B_s = E_s + sum_t F_st rho_t B_t,
    // from the others' rows, bring them to about the others' error (IR sweeps in the sample's
    // trials: 11-14 -> 7-12; the solar Krylov start: -20 % iterations). In a fixed order, so
    // deterministic.
    std::vector<int> unset;
    for (int s = 0; s < S; ++s)
      if (X.row(s).isZero(0.0)) unset.push_back(s);
    Eigen::RowVectorXd y(C);
    for (int pass = 0; pass < 2 && unset.size() < static_cast<std::size_t>(S); ++pass)
      for (int s : unset) {
        y = E.row(s);
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(vf.F, s); e; ++e)
          y.noalias() += (e.value() * rho[e.col()]) * X.row(e.col());
        X.row(s) = y;
      }
  }
  const double max_rho0 = S ? rho.maxCoeff() : 0.0;
  if (settings.krylov_start && max_rho0 > 0.6 && S > 0) {
    // Reflective coatings (rho -> 1) make the Neumann series slow (~23 / (1 - rho) sweeps).
    // A Krylov solve per column gets close first; the sweeps below then only polish and
    // certify the result with the same stopping rule. Columns are independent, so solving
    // them in parallel stays deterministic.
    Eigen::SparseMatrix<double, Eigen::RowMajor> A = -(vf.F * rho.asDiagonal());
    Eigen::SparseMatrix<double, Eigen::RowMajor> I(S, S);
    I.setIdentity();
    A += I;
    A.makeCompressed();
    tbb::parallel_for(0, C, [&](int g) {
      const Eigen::VectorXd b = E.col(g);
      if (b.isZero(0.0)) {  // (I - F diag(rho)) x = 0: x = 0, whatever a warm start said
        X.col(g).setZero();
        return;
      }
      Eigen::BiCGSTAB<Eigen::SparseMatrix<double, Eigen::RowMajor>, Eigen::DiagonalPreconditioner<double>> solver;
      solver.setTolerance(1e-12);
      solver.setMaxIterations(1000);
      solver.compute(A);
      const Eigen::VectorXd x = warm_start ? Eigen::VectorXd(solver.solveWithGuess(b, X.col(g))) : Eigen::VectorXd(solver.solve(b));
      if (solver.info() == Eigen::Success && x.allFinite()) X.col(g) = x;
    });
  }
  RowMatrixXd Y(S, C);
  const double max_rho = max_rho0;
  for (int it = 1; it <= settings.max_iterations; ++it) {
    // Y = E + F diag(rho) X, row by row: rows are independent, so any schedule gives the
    // same bits; the max-reduction below is order-independent too.
    const double change = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, S, 64), 0.0,
        [&](const tbb::blocked_range<int>& r, double m) {
          for (int s = r.begin(); s != r.end(); ++s) {
            auto y = Y.row(s);
            y = E.row(s);
            for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(vf.F, s); e; ++e) {
              const double w = e.value() * rho[e.col()];
              if (w != 0.0) y.noalias() += w * X.row(e.col());
            }
            m = std::max(m, (y - X.row(s)).cwiseAbs().maxCoeff());
          }
          return m;
        },
        [](double a, double b) { return std::max(a, b); });
    X.swap(Y);
    out.iterations = it;
    out.max_change = change;
    // note: with max(rho) < 1 the remaining error is bounded by change * rho / (1 - rho).
    if (change <= settings.tolerance * std::max(1e-3, 1.0 - max_rho)) break;
  }
  if (out.max_change > settings.tolerance * std::max(1e-3, 1.0 - max_rho))
    throw SolverError("Gebhart factors did not converge in " + std::to_string(settings.max_iterations) +
                      " iterations (last change " + std::to_string(out.max_change) + ")");
  for (int s = 0; s < S; ++s) out.max_closure_error = std::max(out.max_closure_error, std::abs(X.row(s).sum() - 1.0));
  out.B = std::move(X);
  return out;
}

}  // namespace thermodec
