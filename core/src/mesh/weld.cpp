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
  // Cells of at least twice the tolerance: a ball of radius `tolerance` then reaches at most
  // the neighbouring cell on the near side of each axis, so a vertex away from cell faces
  // probes one cell, not 27. The floor on the size keeps cell indices within 64 bits.
  const double cell = std::max({2.0 * tolerance, max_abs * 1e-12, 1e-300});
  const double reach = tolerance + cell * 1e-9;  // slack for rounding in the face distances
  const double tol2 = tolerance * tolerance;

  WeldResult out;
  out.new_index.resize(V.rows());
  std::vector<Eigen::Index> kept;  // input rows of surviving vertices
  std::vector<int> next_in_cell;   // per surviving vertex: the previous one in its cell, or -1
  std::unordered_map<Cell, int, CellHash> head;  // cell -> latest surviving vertex in it
  head.reserve(static_cast<std::size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    Cell c;
    std::array<std::array<int, 2>, 3> offsets;  // per axis: 0 and, if near a face, -1 or +1
    std::array<int, 3> num_offsets;
    for (int k = 0; k < 3; ++k) {
      const double x = V(i, k) / cell;
      c[k] = static_cast<std::int64_t>(std::floor(x));
      const double from_low = (x - static_cast<double>(c[k])) * cell;
      offsets[k] = {0, 0};
      num_offsets[k] = 1;
      if (from_low <= reach) offsets[k][num_offsets[k]++] = -1;
      else if (cell - from_low <= reach) offsets[k][num_offsets[k]++] = 1;
    }
    int found = -1;
    for (int a = 0; a < num_offsets[0]; ++a)
      for (int b = 0; b < num_offsets[1]; ++b)
        for (int d = 0; d < num_offsets[2]; ++d) {
          auto it = head.find({c[0] + offsets[0][a], c[1] + offsets[1][b], c[2] + offsets[2][d]});
          if (it == head.end()) continue;
          for (int id = it->second; id >= 0; id = next_in_cell[id])
            // Earliest surviving vertex wins, whatever order the cells are visited: deterministic.
            if ((found < 0 || id < found) && (V.row(kept[id]) - V.row(i)).squaredNorm() <= tol2) found = id;
        }
    if (found < 0) {
      found = static_cast<int>(kept.size());
      kept.push_back(i);
      auto [it, added] = head.try_emplace(c, found);
      next_in_cell.push_back(added ? -1 : it->second);
      it->second = found;
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
