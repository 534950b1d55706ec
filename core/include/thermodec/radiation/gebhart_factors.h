#pragma once
//! Gebhart factors of diffuse grey surfaces at face (surface-side) level, for any band: IR
//! (absorptivity = emissivity) or solar (absorptivity = alpha).
#include <Eigen/Core>

#include "thermodec/radiation/face_view_factors.h"

namespace thermodec {

struct GebhartSettings {
  //! Bound on the error of any entry of B [-]. 1e-8 lies 4-5 orders under the Monte Carlo
  //! error of the view factors it is solved from (~1e-3 of a row at 1000 rays per side) and
  //! moves a node's temperature by ~T 1e-8 / 4 (~1e-6 K); each factor of 10 tighter costs
  //! rounds that reach ever more sides (a Juno reduction trial: 25 000 of 31 000 sides pushed
  //! per round at 1e-10, ~10 000 at 1e-8).
  double tolerance = 1e-8;
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
  int iterations = 0;           //!< rounds (see gebhart_factors)
  double max_change = 0.0;      //!< largest residual entry at the end (<= tolerance x (1 - max rho))
  double max_closure_error = 0.0;  //!< max_s |sum_g B(s, g) - 1|
};

//! Solves B = F diag(a) P + F diag(1 - a) B, i.e. (I - F diag(rho)) B = F diag(a) P with
//! P(t, g) = [group_of_side(t) == g], plus the space column, by rounds of the reflection
//! (Neumann) series driven by the residual R = F diag(a) P + F diag(rho) X - X: each round,
//! every side whose residual row exceeds tolerance x (1 - max rho) passes it on (X_s += R_s,
//! and the rows that see s receive F(t, s) rho_s R_s), the others wait. From scratch every row
//! takes part and a round is a Jacobi sweep (error after k rounds at most max(rho)^k); from a
//! warm start that differs near a few nodes only those rows do, so a round costs a fraction of
//! a sweep. It stops when no residual entry exceeds the threshold, certified by a residual
//! computed afresh. When max(rho) > 0.6, a BiCGSTAB solve per column (Eigen, diagonal
//! preconditioner; from the warm start if one is given) provides the start and the rounds only
//! polish and certify it. Deterministic for any thread count.
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
