#include "thermodec/radiation/gebhart_factors.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/IterativeLinearSolvers>

#include "thermodec/common/errors.h"
#include "reflection_operator.h"

namespace thermodec {

Eigen::VectorXi node_groups(const SurfaceSides& sides, int num_nodes) {
  Eigen::VectorXi g(sides.size());
  for (int s = 0; s < sides.size(); ++s) g[s] = (sides.node[s] >= 0 && sides.node[s] < num_nodes) ? sides.node[s] : num_nodes;
  return g;
}

namespace {

using SparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor>;
using detail::ReflectionJacobi;
using detail::ReflectionOperator;

void check_inputs(const FaceViewFactors& vf, const Eigen::VectorXd& absorptivity, const Eigen::VectorXi& group_of_side,
                  int num_groups, const RowMatrixXd* warm_start) {
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
}

// Direct term E(s, g) = sum_t F(s, t) a_t [t in g]; space column (g = G) = F(s, space).
RowMatrixXd direct_term(const FaceViewFactors& vf, const Eigen::VectorXd& absorptivity,
                        const Eigen::VectorXi& group_of_side, int G) {
  const int S = vf.sides.size();
  RowMatrixXd E = RowMatrixXd::Zero(S, G + 1);
  tbb::parallel_for(tbb::blocked_range<int>(0, S, 64), [&](const tbb::blocked_range<int>& r) {
    for (int s = r.begin(); s != r.end(); ++s) {
      for (SparseRows::InnerIterator it(vf.F, s); it; ++it) E(s, group_of_side[it.col()]) += it.value() * absorptivity[it.col()];
      E(s, G) = vf.to_space[s];
    }
  });
  return E;
}

// Rows a warm start leaves at zero (no solution row is: each sums to 1) are a reduction
// trial's new sides. Two in-place passes over just them, B_s = E_s + sum_t F_st rho_t B_t,
// from the others' rows, bring them to about the others' error (the sample's trials: IR sweeps
// 11-14 -> 7-12; the solar Krylov start: -20 % iterations). In a fixed order: deterministic.
void fill_new_rows(const FaceViewFactors& vf, const Eigen::VectorXd& rho, const RowMatrixXd& E, RowMatrixXd& X) {
  const int S = X.rows();
  std::vector<int> unset;
  for (int s = 0; s < S; ++s)
    if (X.row(s).isZero(0.0)) unset.push_back(s);
  Eigen::RowVectorXd y(X.cols());
  for (int pass = 0; pass < 2 && unset.size() < static_cast<std::size_t>(S); ++pass)
    for (int s : unset) {
      y = E.row(s);
      for (SparseRows::InnerIterator e(vf.F, s); e; ++e) y.noalias() += (e.value() * rho[e.col()]) * X.row(e.col());
      X.row(s) = y;
    }
}

// Reflective coatings (rho -> 1) make the reflection series slow (~23 / (1 - rho) rounds). A
// Krylov solve per column (BiCGSTAB, Jacobi preconditioner) gets close first; the rounds
// then only polish and certify it with the same stopping rule. Columns are independent, so
// solving them in parallel stays deterministic. The operator I - F diag(rho) is applied from F
// itself (ReflectionOperator), never formed: a second copy of F's entries would double the
// solve's memory (1.4 GB more on a 100k-face model).
void krylov_start(const FaceViewFactors& vf, const Eigen::VectorXd& rho, const RowMatrixXd& E, bool warm, RowMatrixXd& X) {
  const ReflectionOperator A(vf.F, rho);
  tbb::parallel_for(0, static_cast<int>(X.cols()), [&](int g) {
    const Eigen::VectorXd b = E.col(g);
    if (b.isZero(0.0)) {  // (I - F diag(rho)) x = 0: x = 0, whatever a warm start said
      X.col(g).setZero();
      return;
    }
    Eigen::BiCGSTAB<ReflectionOperator, ReflectionJacobi> solver;
    solver.setTolerance(1e-12);
    solver.setMaxIterations(1000);
    solver.compute(A);
    const Eigen::VectorXd x = warm ? Eigen::VectorXd(solver.solveWithGuess(b, X.col(g))) : Eigen::VectorXd(solver.solve(b));
    if (solver.info() == Eigen::Success && x.allFinite()) X.col(g) = x;
  });
}

// The rounds' arithmetic: y[0, C) += sum over row t of F of F(t, s) rho_s src[k], with k = s
// (no `slot`) or k = slot[s] (entries with slot[s] < 0 skipped); true if any entry was taken.
// Plain loops, so that the compiler vectorises the AVX2 clone (4 doubles per instruction, on
// CPUs that have it, chosen at load time) as well as the default one; AVX2 without FMA rounds
// every product and sum as the default clone does: the same bits on any x86-64.
#if defined(__GNUC__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
bool gather_row(const int* cols, const double* vals, int nnz, const double* rho, const int* slot,
                const double* src, int C, double* __restrict y) {
  bool taken = false;
  for (int e = 0; e < nnz; ++e) {
    const int k = slot ? slot[cols[e]] : cols[e];
    if (k < 0) continue;
    taken = true;
    const double w = vals[e] * rho[cols[e]];
    if (w == 0.0) continue;
    const double* __restrict x = src + std::size_t(k) * C;
    for (int c = 0; c < C; ++c) y[c] += w * x[c];
  }
  return taken;
}

// y[0, C) += w x[0, C), with gather_row's arithmetic (the same clones, no fused multiply-add):
// a row updated entry by entry here gets the bits gather_row would give it.
#if defined(__GNUC__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void add_scaled_row(double w, const double* __restrict x, int C, double* __restrict y) {
  for (int c = 0; c < C; ++c) y[c] += w * x[c];
}

// F's rows as index arrays (compressed storage).
struct RowsOfF {
  SparseRows copy;  // (only if F was not compressed)
  const int *outer, *cols;
  const double* vals;
  explicit RowsOfF(const SparseRows& F) : copy(F.isCompressed() ? SparseRows() : F) {
    copy.makeCompressed();
    const SparseRows& f = F.isCompressed() ? F : copy;
    outer = f.outerIndexPtr();
    cols = f.innerIndexPtr();
    vals = f.valuePtr();
  }
  int nnz(int t) const { return outer[t + 1] - outer[t]; }
};

// F's columns as index lists: column s holds the rows t that see side s (F(t, s) != 0 stored)
// and each entry's position in F's storage. Who receives what a pushed side reflects, without
// scanning all of F. Built once per solve (two passes over F's indices), on the first round
// that pushes few rows.
struct ColumnsOfF {
  std::vector<int> outer;  // S + 1 offsets into row / entry
  std::vector<int> row;    // receiving row t, ascending within a column
  std::vector<int> entry;  // position of F(t, s) in RowsOfF's cols / vals
  ColumnsOfF(const RowsOfF& f, int S) : outer(S + 1, 0) {
    const int nnz = f.outer[S];
    for (int e = 0; e < nnz; ++e) ++outer[f.cols[e] + 1];
    for (int s = 0; s < S; ++s) outer[s + 1] += outer[s];
    row.resize(nnz);
    entry.resize(nnz);
    std::vector<int> next(outer.begin(), outer.end() - 1);
    for (int t = 0; t < S; ++t)
      for (int e = f.outer[t]; e < f.outer[t + 1]; ++e) {
        const int q = next[f.cols[e]]++;
        row[q] = t;
        entry[q] = e;
      }
  }
};

// A round pushing at most S / kFewPushedRows rows reaches its receivers through ColumnsOfF;
// more, and the plain scan of every row (gather_row with `slot`) costs no more.
constexpr int kFewPushedRows = 8;

// R_t += sum_s F(t, s) rho_s P[slot[s]] over the pushed sides s, through F's columns: the
// receiving rows, each summed over its entries in F's storage order (the order gather_row
// takes them in: the same bits). `pushed` is ascending and F's rows hold their columns in
// ascending order (Eigen's compressed storage), so the counting sort below lists each row's
// entries in that order already. `row_max` follows every receiving row.
void push_through_columns(const RowsOfF& f, const ColumnsOfF& cf, const Eigen::VectorXd& rho,
                          const std::vector<int>& pushed, const std::vector<int>& slot, const RowMatrixXd& P,
                          RowMatrixXd& R, Eigen::VectorXd& row_max) {
  const int S = static_cast<int>(R.rows()), C = static_cast<int>(R.cols());
  // Receiving rows and their entries (counting sort by row).
  std::vector<int> start(S + 1, 0);
  for (int s : pushed)
    for (int q = cf.outer[s]; q < cf.outer[s + 1]; ++q) ++start[cf.row[q] + 1];
  std::vector<int> receivers;
  for (int t = 0; t < S; ++t) {
    if (start[t + 1] > 0) receivers.push_back(t);
    start[t + 1] += start[t];
  }
  std::vector<int> entries(start[S]), next(start.begin(), start.end() - 1);
  for (int s : pushed)
    for (int q = cf.outer[s]; q < cf.outer[s + 1]; ++q) entries[next[cf.row[q]]++] = cf.entry[q];
  const int m = static_cast<int>(receivers.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, m, 16), [&](const tbb::blocked_range<int>& r) {
    for (int k = r.begin(); k != r.end(); ++k) {
      const int t = receivers[k];
      for (const int* e = entries.data() + start[t], *last = entries.data() + start[t + 1]; e != last; ++e) {
        const int s = f.cols[*e];
        const double w = f.vals[*e] * rho[s];
        if (w == 0.0) continue;
        add_scaled_row(w, P.data() + std::size_t(slot[s]) * C, C, &R(t, 0));
      }
      row_max[t] = R.row(t).cwiseAbs().maxCoeff();
    }
  });
}

// Residual R = E + F diag(rho) X - X, row by row (rows are independent: any schedule gives
// the same bits), and each row's largest |entry| in `row_max`.
void residual(const RowsOfF& f, const Eigen::VectorXd& rho, const RowMatrixXd& E, const RowMatrixXd& X,
              RowMatrixXd& R, Eigen::VectorXd& row_max) {
  const int C = static_cast<int>(X.cols());
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(X.rows()), 64), [&](const tbb::blocked_range<int>& r) {
    for (int s = r.begin(); s != r.end(); ++s) {
      R.row(s) = E.row(s) - X.row(s);
      gather_row(f.cols + f.outer[s], f.vals + f.outer[s], f.nnz(s), rho.data(), nullptr, X.data(), C, &R(s, 0));
      row_max[s] = R.row(s).cwiseAbs().maxCoeff();
    }
  });
}

// One round: every side whose residual row exceeds `threshold` takes it into X (one more
// reflection of what it has not yet passed on), and the residual follows exactly,
// R_t += sum_s F(t, s) rho_s P_s over the pushed rows P. With the reference's solution as
// the start, only the few percent of the rows near a trial's change carry a residual above
// the threshold (Juno: 200-1 600 of 31 000 at first), so a round costs the pushed sides'
// columns of F (ColumnsOfF), not a full sweep; a round pushing many rows scans F's rows
// instead. Rows are updated independently: deterministic, and the same bits either way.
void push_round(const RowsOfF& f, std::unique_ptr<ColumnsOfF>& columns, const Eigen::VectorXd& rho, double threshold,
                RowMatrixXd& X, RowMatrixXd& R, Eigen::VectorXd& row_max, std::vector<int>& slot, RowMatrixXd& P) {
  const int S = X.rows(), C = X.cols();
  std::vector<int> pushed;
  for (int s = 0; s < S; ++s)
    if (row_max[s] > threshold) pushed.push_back(s);
  const int n = static_cast<int>(pushed.size());
  if (n == 0) return;
  P.resize(n, C);
  for (int k = 0; k < n; ++k) {
    const int s = pushed[k];
    P.row(k) = R.row(s);
    X.row(s) += P.row(k);
    R.row(s).setZero();
    row_max[s] = 0.0;
    slot[s] = k;
  }
  if (static_cast<long long>(n) * kFewPushedRows <= S) {
    if (!columns) columns = std::make_unique<ColumnsOfF>(f, S);
    push_through_columns(f, *columns, rho, pushed, slot, P, R, row_max);
  } else {
    tbb::parallel_for(tbb::blocked_range<int>(0, S, 64), [&](const tbb::blocked_range<int>& r) {
      for (int t = r.begin(); t != r.end(); ++t)
        if (gather_row(f.cols + f.outer[t], f.vals + f.outer[t], f.nnz(t), rho.data(), slot.data(), P.data(), C, &R(t, 0)))
          row_max[t] = R.row(t).cwiseAbs().maxCoeff();
    });
  }
  for (int s : pushed) slot[s] = -1;
}

}  // namespace

GebhartFactors gebhart_factors(const FaceViewFactors& vf, const Eigen::VectorXd& absorptivity,
                               const Eigen::VectorXi& group_of_side, int num_groups, const GebhartSettings& settings,
                               const RowMatrixXd* warm_start) {
  check_inputs(vf, absorptivity, group_of_side, num_groups, warm_start);
  const int S = vf.sides.size(), C = num_groups + 1;
  const Eigen::VectorXd rho = (1.0 - absorptivity.array()).matrix();
  const RowMatrixXd E = direct_term(vf, absorptivity, group_of_side, num_groups);
  RowMatrixXd X = warm_start ? *warm_start : E;
  if (warm_start) fill_new_rows(vf, rho, E, X);
  const double max_rho = S ? rho.maxCoeff() : 0.0;
  if (settings.krylov_start && max_rho > 0.6 && S > 0) krylov_start(vf, rho, E, warm_start != nullptr, X);

  // Stop when no residual entry exceeds tolerance x (1 - max rho): the remaining error of B is
  // then below the tolerance, since each further reflection passes on at most max(rho) of it.
  const double threshold = settings.tolerance * std::max(1e-3, 1.0 - max_rho);
  GebhartFactors out;
  RowMatrixXd R(S, C), P;
  Eigen::VectorXd row_max(S);
  std::vector<int> slot(S, -1);
  const RowsOfF f(vf.F);
  std::unique_ptr<ColumnsOfF> columns;  // built when a round first pushes few rows
  residual(f, rho, E, X, R, row_max);
  bool fresh = true;  // R computed afresh since the last round
  for (int round = 0;; ++round) {
    out.iterations = round;
    out.max_change = S ? row_max.maxCoeff() : 0.0;
    if (out.max_change <= threshold && !fresh) {
      // Certify with a residual computed afresh (the tracked one differs by rounding only).
      residual(f, rho, E, X, R, row_max);
      fresh = true;
      out.max_change = S ? row_max.maxCoeff() : 0.0;
    }
    if (out.max_change <= threshold || round == settings.max_iterations) break;
    push_round(f, columns, rho, threshold, X, R, row_max, slot, P);
    fresh = false;
  }
  if (out.max_change > threshold)
    throw SolverError("Gebhart factors did not converge in " + std::to_string(settings.max_iterations) +
                      " iterations (last residual " + std::to_string(out.max_change) + ")");
  for (int s = 0; s < S; ++s) out.max_closure_error = std::max(out.max_closure_error, std::abs(X.row(s).sum() - 1.0));
  out.B = std::move(X);
  return out;
}

}  // namespace thermodec
