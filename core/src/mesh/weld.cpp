#include "thermodec/mesh/weld.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "thermodec/common/errors.h"

namespace thermodec {
namespace {
using Cell = std::array<std::int64_t, 3>;
struct CellHash {
  std::size_t operator()(const Cell& c) const {
    std::uint64_t h = 1469598103934665603ull;
    for (auto v : c) h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};
}  // namespace

WeldResult weld_vertices(const Eigen::MatrixXd& V, double tolerance) {
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance))
    throw InvalidInput("weld tolerance must be a finite number >= 0, got " + std::to_string(tolerance));
  double max_abs = 0.0;
  for (Eigen::Index i = 0; i < V.size(); ++i) {
    if (!std::isfinite(V.data()[i])) throw InvalidInput("cannot weld vertices with non-finite coordinates");
    max_abs = std::max(max_abs, std::abs(V.data()[i]));
  }
  // The grid cell must be at least the tolerance (so the 27 neighbouring cells hold every
  // candidate) and large enough that cell indices fit in 64 bits; tolerance 0 then still
  // finds exact duplicates, which always share a cell.
  const double cell = std::max({tolerance, max_abs * 1e-12, 1e-300});
  const double tol2 = tolerance * tolerance;

  WeldResult out;
  out.new_index.resize(V.rows());
  std::vector<Eigen::Index> kept;  // input rows of surviving vertices
  std::unordered_map<Cell, std::vector<int>, CellHash> grid;  // cell -> surviving vertex ids
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    Cell c;
    for (int k = 0; k < 3; ++k) c[k] = static_cast<std::int64_t>(std::floor(V(i, k) / cell));
    int found = -1;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (int id : it->second)
            // Earliest surviving vertex wins, whatever cell order we visit: deterministic.
            if ((found < 0 || id < found) && (V.row(kept[id]) - V.row(i)).squaredNorm() <= tol2) found = id;
        }
    if (found < 0) {
      found = static_cast<int>(kept.size());
      kept.push_back(i);
      grid[c].push_back(found);
    }
    out.new_index[i] = found;
  }
  out.V.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t j = 0; j < kept.size(); ++j) out.V.row(static_cast<Eigen::Index>(j)) = V.row(kept[j]);
  return out;
}

int weld_mesh_vertices(Eigen::MatrixXd& V, Eigen::MatrixXi& F, double tolerance) {
  WeldResult w = weld_vertices(V, tolerance);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < F.cols(); ++k) F(f, k) = w.new_index[F(f, k)];
  const int removed = static_cast<int>(V.rows() - w.V.rows());
  V = std::move(w.V);
  return removed;
}

}  // namespace thermodec
