#include "thermodec/mesh/geometry_range.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "thermodec/common/errors.h"

namespace thermodec {

void check_geometry_range(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::string& file) {
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    for (Eigen::Index k = 0; k < V.cols(); ++k) {
      const double x = V(v, k);
      if (std::isfinite(x) && std::abs(x) <= kMaxCoordinate) continue;
      char value[40];
      std::snprintf(value, sizeof value, "%g", x);
      throw InvalidInput(file + ": vertex " + std::to_string(v) + ": coordinate " + value +
                         (std::isfinite(x) ? " is beyond ±1e12, where areas, normals and distances overflow"
                                           : " is not finite") +
                         " (is the file in the units it claims? rescale it)");
    }
  // Within that range an area cannot overflow; the sum is checked anyway, as the last guard.
  double total = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (F.row(f).minCoeff() < 0 || F.row(f).maxCoeff() >= V.rows()) continue;  // the readers refuse those
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    total += (b - a).cross(c - a).norm();
  }
  if (!std::isfinite(total)) throw InvalidInput(file + ": the total area is not finite");
}

}  // namespace thermodec
