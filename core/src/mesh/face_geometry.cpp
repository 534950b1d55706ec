#include "thermodec/mesh/face_geometry.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace thermodec {
namespace {
Eigen::Vector3d corner(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f, int k) {
  return V.row(F(f, k)).transpose();
}
Eigen::Vector3d doubled_area_vector(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const Eigen::Vector3d a = corner(V, F, f, 0);
  return (corner(V, F, f, 1) - a).cross(corner(V, F, f, 2) - a);
}
}  // namespace

Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::VectorXd A(F.rows());
  for (int f = 0; f < F.rows(); ++f) A[f] = 0.5 * doubled_area_vector(V, F, f).norm();
  return A;
}

Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(F.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) {
    if (is_degenerate_face(V, F, f)) continue;
    N.row(f) = doubled_area_vector(V, F, f).normalized().transpose();
  }
  return N;
}

bool is_degenerate_face(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
  if (a == b || b == c || a == c) return true;
  const Eigen::Vector3d p = corner(V, F, f, 0), q = corner(V, F, f, 1), r = corner(V, F, f, 2);
  const double longest2 = std::max({(q - p).squaredNorm(), (r - q).squaredNorm(), (p - r).squaredNorm()});
  // Relative test: a sliver is only "zero area" when its corners are collinear to within
  // the precision of double arithmetic, whatever the mesh's scale.
  return (q - p).cross(r - p).norm() <= 1e-12 * longest2;
}

std::vector<int> degenerate_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<int> out;
  for (int f = 0; f < F.rows(); ++f)
    if (is_degenerate_face(V, F, f)) out.push_back(f);
  return out;
}

}  // namespace thermodec
