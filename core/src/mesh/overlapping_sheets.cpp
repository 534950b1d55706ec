#include "thermodec/mesh/overlapping_sheets.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vector>

#include "thermodec/mesh/face_geometry.h"

namespace thermodec {

std::vector<char> overlapping_sheet_faces(const Mesh& m, const Eigen::VectorXi& two_sided, double distance) {
  const int nf = m.num_faces();
  std::vector<char> keep(nf, 1);
  const Eigen::MatrixXd N = face_normals(m.V, m.F);
  const Eigen::VectorXd A = face_areas(m.V, m.F);
  auto corner = [&](int f, int k) -> Eigen::Vector3d { return m.V.row(m.F(f, k)).transpose(); };
  std::vector<int> sheet;
  for (int f = 0; f < nf; ++f)
    if (two_sided[f] && A[f] > 0) sheet.push_back(f);
  const int ns = static_cast<int>(sheet.size());
  std::vector<Eigen::AlignedBox3d> box(nf);
  for (int f : sheet)
    for (int k = 0; k < 3; ++k) box[f].extend(corner(f, k));
  // Candidate partners: parallel two-sided faces whose boxes meet (sweep along x).
  std::vector<int> by_x = sheet;
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) {
    return std::make_pair(box[a].min().x(), a) < std::make_pair(box[b].min().x(), b);
  });
  std::vector<std::vector<int>> partners(nf);
  for (int i = 0; i < ns; ++i) {
    const int f = by_x[i];
    for (int j = i + 1; j < ns && box[by_x[j]].min().x() <= box[f].max().x() + distance; ++j) {
      const int g = by_x[j];
      if (std::abs(N.row(f).dot(N.row(g))) < 1 - 1e-4) continue;
      Eigen::AlignedBox3d bf = box[f];
      bf.min().array() -= distance;
      bf.max().array() += distance;
      if (!bf.intersects(box[g])) continue;
      partners[f].push_back(g);
      partners[g].push_back(f);
    }
  }
  static constexpr double kBary[7][3] = {{1. / 3, 1. / 3, 1. / 3}, {.6, .2, .2},  {.2, .6, .2}, {.2, .2, .6},
                                         {.45, .45, .1},         {.1, .45, .45}, {.45, .1, .45}};
  std::vector<int> order = sheet;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return std::make_pair(-A[a], a) < std::make_pair(-A[b], b); });
  std::vector<char> done(nf, 0);
  for (int f : order) {
    done[f] = 1;
    if (partners[f].empty()) continue;
    int covered = 0;
    for (int s = 0; s < 7; ++s) {
      const Eigen::Vector3d x = kBary[s][0] * corner(f, 0) + kBary[s][1] * corner(f, 1) + kBary[s][2] * corner(f, 2);
      for (int g : partners[f]) {
        if (!done[g] || !keep[g]) continue;  // only faces kept before f cover it
        const Eigen::Vector3d n = N.row(g).transpose(), a = corner(g, 0), b = corner(g, 1), c = corner(g, 2);
        const double h = (x - a).dot(n);
        if (std::abs(h) > distance) continue;
        const Eigen::Vector3d y = x - h * n;
        auto inside = [&](const Eigen::Vector3d& u, const Eigen::Vector3d& v) { return (v - u).cross(y - u).dot(n) >= 0; };
        if (inside(a, b) && inside(b, c) && inside(c, a)) {
          ++covered;
          break;
        }
      }
    }
    if (covered >= 4) keep[f] = 0;
  }
  return keep;
}

}  // namespace thermodec
