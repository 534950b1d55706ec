#pragma once
// Helpers shared by the decimation benchmarks: CPU time and per-node projected areas.
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "thermodec/mesh/mesh.h"

namespace thermodec::bench {

//! User + system CPU time of this process so far [s].
inline double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

//! P[node][k] = sum over the node's faces of max(0, N_f . d_k) [m^2], d_k on a Fibonacci
//! lattice of ndir directions: what a node shows to a distant observer in direction d_k.
inline std::vector<std::vector<double>> projected_areas(const Mesh& m, int nodes, int ndir) {
  std::vector<Eigen::Vector3d> dirs;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < ndir; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / ndir, r = std::sqrt(1.0 - z * z);
    dirs.emplace_back(r * std::cos(golden * k), r * std::sin(golden * k), z);
  }
  std::vector<std::vector<double>> p(nodes, std::vector<double>(ndir, 0.0));
  for (int f = 0; f < m.num_faces(); ++f) {
    const int node = m.face_node[f];
    if (node < 0) continue;
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    const Eigen::Vector3d n = 0.5 * (b - a).cross(c - a);
    for (int k = 0; k < ndir; ++k) p[node][k] += std::max(0.0, n.dot(dirs[k]));
  }
  return p;
}

}  // namespace thermodec::bench
