#pragma once
//! Gebhart factors of diffuse grey surfaces at face (surface-side) level, for any band: IR
//! (absorptivity = emissivity) or solar (absorptivity = alpha).
#include <Eigen/Core>

#include "thermodec/radiation/face_view_factors.h"

namespace thermodec {

struct GebhartSettings {
  double tolerance = 1e-10;  //!< stop when no entry of B changes by more than this [-]
  int max_iterations = 10000;
  //! With max(rho) > 0.6, start from a BiCGSTAB solve per column (false: the sweeps alone,
  //! from the warm start or the direct term; for checking one against the other).
  bool krylov_start = true;
};

//! Row-major dense matrix (row = surface side), the layout the sparse products stream over.
using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct GebhartFactors {
  //! #S x (G + 1): B(s, g) = fraction of the power leaving side s diffusely (emitted or
  //! reflected) that is finally absorbed by group g after any number of diffuse reflections;
  //! the last column (g = G) is the fraction lost to space. Rows sum to 1 (closure).
  RowMatrixXd B;
  int iterations = 0;
  double max_change = 0.0;      //!< last iteration's largest change (<= tolerance on success)
  double max_closure_error = 0.0;  //!< max_s |sum_g B(s, g) - 1|
};

//! Solves B = F diag(a) P + F diag(1 - a) B, i.e. (I - F diag(rho)) B = F diag(a) P with
//! P(t, g) = [group_of_side(t) == g], plus the space column, by a parallel Jacobi (Neumann
//! series) iteration over sparse F: each sweep absorbs one more reflection, so the error after
//! k sweeps is at most max(rho)^k; it stops when no entry changes by more than
//! tolerance x (1 - max rho). When max(rho) > 0.6, a BiCGSTAB solve per column (Eigen,
//! diagonal preconditioner; from the warm start if one is given) provides the start and the
//! sweeps only polish and certify it. Deterministic for any thread count.
//!
//! IR: absorptivity = side emissivity; GR between groups I, J = sum_{s in I} A_s eps_s B(s, J).
//! Solar: a side receiving direct flux Q_s [W] makes group g absorb
//! Q_s (alpha_s [s in g] + (1 - alpha_s) B(s, g)).
//!
//! \param absorptivity #S values in (0, 1].
//! \param group_of_side #S values in [0, num_groups).
//! \param warm_start optional #S x (G + 1) initial guess (e.g. a previous solution); its rows
//!        left at zero (sides new to it) are first filled from the others by two local passes.
//! \throw InvalidInput on size mismatch or values out of range; SolverError if not converged.
GebhartFactors gebhart_factors(const FaceViewFactors& vf, const Eigen::VectorXd& absorptivity,
                               const Eigen::VectorXi& group_of_side, int num_groups,
                               const GebhartSettings& settings = {}, const RowMatrixXd* warm_start = nullptr);

//! Group index of each side: its node, or `num_nodes` (an extra "unassigned" group) if < 0.
Eigen::VectorXi node_groups(const SurfaceSides& sides, int num_nodes);

}  // namespace thermodec
