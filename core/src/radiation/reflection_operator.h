#pragma once
// Private to core/src/radiation: the operator A = I - F diag(rho) of the Gebhart system
// (I - F diag(rho)) B = F diag(a) P, applied from the view factors F without forming A, for
// Eigen's iterative solvers (the matrix-free interface of Eigen/IterativeLinearSolvers).
#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

namespace thermodec::detail {
class ReflectionOperator;
}

namespace Eigen::internal {
// Solvers ask the operator for the traits of a sparse matrix (scalar, index, storage order).
template <>
struct traits<thermodec::detail::ReflectionOperator> : public traits<SparseMatrix<double, RowMajor>> {};
}  // namespace Eigen::internal

namespace thermodec::detail {

class ReflectionOperator : public Eigen::EigenBase<ReflectionOperator> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic, IsRowMajor = true };

  //! `F` #S x #S view factors, `rho` #S reflectances [-]; both must outlive the operator.
  ReflectionOperator(const Eigen::SparseMatrix<double, Eigen::RowMajor>& F, const Eigen::VectorXd& rho)
      : F_(&F), rho_(&rho) {}
  Eigen::Index rows() const { return F_->rows(); }
  Eigen::Index cols() const { return F_->cols(); }

  template <class Rhs>
  Eigen::Product<ReflectionOperator, Rhs, Eigen::AliasFreeProduct> operator*(const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<ReflectionOperator, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }

  //! y += alpha (x - F (rho .* x)).
  template <class Dest, class Rhs>
  void apply_add(Dest& y, const Rhs& x, double alpha) const {
    const Eigen::VectorXd rx = rho_->cwiseProduct(x);
    y.noalias() += alpha * (x - (*F_) * rx);
  }

  //! 1 / A_ss = 1 / (1 - F_ss rho_s): the Jacobi preconditioner.
  Eigen::VectorXd inverse_diagonal() const {
    Eigen::VectorXd d = Eigen::VectorXd::Ones(rows());
    for (Eigen::Index s = 0; s < rows(); ++s) {
      const double a = 1.0 - F_->coeff(s, s) * (*rho_)[s];
      if (a != 0.0) d[s] = 1.0 / a;
    }
    return d;
  }

 private:
  const Eigen::SparseMatrix<double, Eigen::RowMajor>* F_;
  const Eigen::VectorXd* rho_;
};

//! Jacobi preconditioning of ReflectionOperator (Eigen's DiagonalPreconditioner needs stored entries).
class ReflectionJacobi {
 public:
  ReflectionJacobi() = default;
  template <class M>
  ReflectionJacobi& analyzePattern(const M&) { return *this; }
  template <class M>
  ReflectionJacobi& factorize(const M& A) {
    inverse_ = A.inverse_diagonal();
    return *this;
  }
  template <class M>
  ReflectionJacobi& compute(const M& A) { return factorize(A); }
  template <class Rhs>
  Eigen::VectorXd solve(const Rhs& b) const { return inverse_.cwiseProduct(b); }
  Eigen::ComputationInfo info() const { return Eigen::Success; }

 private:
  Eigen::VectorXd inverse_;
};

}  // namespace thermodec::detail

namespace Eigen::internal {
template <class Rhs>
struct generic_product_impl<thermodec::detail::ReflectionOperator, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<thermodec::detail::ReflectionOperator, Rhs,
                                generic_product_impl<thermodec::detail::ReflectionOperator, Rhs>> {
  using Scalar = typename Product<thermodec::detail::ReflectionOperator, Rhs>::Scalar;
  template <class Dest>
  static void scaleAndAddTo(Dest& dst, const thermodec::detail::ReflectionOperator& A, const Rhs& x, const Scalar& alpha) {
    A.apply_add(dst, x, alpha);
  }
};
}  // namespace Eigen::internal
