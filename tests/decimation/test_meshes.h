#pragma once
// Small meshes built by hand for the decimation and repair tests.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec::test {

struct MeshBuilder {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  std::vector<int> node, material, back;
  std::map<std::tuple<long, long, long>, int> index;  // welds equal grid points

  int vertex(const Eigen::Vector3d& p) {
    const auto key = std::make_tuple(std::lround(p.x() * 1e9), std::lround(p.y() * 1e9), std::lround(p.z() * 1e9));
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    v.push_back(p);
    index.emplace(key, static_cast<int>(v.size()) - 1);
    return static_cast<int>(v.size()) - 1;
  }
  int raw_vertex(const Eigen::Vector3d& p) {  // never welded (for non-conforming inputs)
    v.push_back(p);
    return static_cast<int>(v.size()) - 1;
  }
  void face(int a, int b, int c, int n, int mat = -1, int bk = -1) {
    f.emplace_back(a, b, c);
    node.push_back(n);
    material.push_back(mat);
    back.push_back(bk);
  }
  // n x n grid quad (origin o, edge vectors u, w), two triangles per cell, normal u x w.
  void grid(const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& w, int n,
            int node_id, int mat = -1, int bk = -1) {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const int a = vertex(o + u * i / n + w * j / n), b = vertex(o + u * (i + 1) / n + w * j / n);
        const int c = vertex(o + u * (i + 1) / n + w * (j + 1) / n), d = vertex(o + u * i / n + w * (j + 1) / n);
        if ((i + j) % 2 == 0) {
          face(a, b, c, node_id, mat, bk);
          face(a, c, d, node_id, mat, bk);
        } else {
          face(a, b, d, node_id, mat, bk);
          face(b, c, d, node_id, mat, bk);
        }
      }
  }
  Mesh build(int num_nodes) const {
    Mesh m;
    m.V.resize(static_cast<int>(v.size()), 3);
    for (size_t i = 0; i < v.size(); ++i) m.V.row(static_cast<int>(i)) = v[i];
    m.F.resize(static_cast<int>(f.size()), 3);
    m.face_node.resize(static_cast<int>(f.size()));
    m.face_material.resize(static_cast<int>(f.size()));
    m.face_back_material.resize(static_cast<int>(f.size()));
    for (size_t i = 0; i < f.size(); ++i) {
      const int k = static_cast<int>(i);
      m.F.row(k) = f[i];
      m.face_node[k] = node[i];
      m.face_material[k] = material[i];
      m.face_back_material[k] = back[i];
    }
    for (int i = 0; i < num_nodes; ++i) m.node_names.push_back("node" + std::to_string(i));
    return m;
  }
};

// Axis-aligned box [0,sx]x[0,sy]x[0,sz], outward normals, n x n grid per side; node of side
// k = first_node + k when six_nodes, else first_node for all.
inline void add_box(MeshBuilder& b, const Eigen::Vector3d& lo, const Eigen::Vector3d& size, int n,
                    bool six_nodes, int first_node) {
  const Eigen::Vector3d X(size.x(), 0, 0), Y(0, size.y(), 0), Z(0, 0, size.z());
  auto nd = [&](int k) { return six_nodes ? first_node + k : first_node; };
  b.grid(lo, Y, X, n, nd(0));          // z = lo (normal -z)
  b.grid(lo + Z, X, Y, n, nd(1));      // z = hi (+z)
  b.grid(lo, X, Z, n, nd(2));          // y = lo (-y)
  b.grid(lo + Y, Z, X, n, nd(3));      // y = hi (+y)
  b.grid(lo, Z, Y, n, nd(4));          // x = lo (-x)
  b.grid(lo + X, Y, Z, n, nd(5));      // x = hi (+x)
}

inline Mesh subdivided_box(int n, bool six_nodes) {
  MeshBuilder b;
  add_box(b, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), n, six_nodes, 0);
  return b.build(six_nodes ? 6 : 1);
}

// UV sphere (closed, outward), `rings` x `segments`; node by quadrant of longitude + first_node.
inline void add_sphere(MeshBuilder& b, const Eigen::Vector3d& c, double r, int rings, int segments,
                       int first_node) {
  auto p = [&](int i, int j) -> int {
    if (i == 0) return b.vertex(c + Eigen::Vector3d(0, 0, r));
    if (i == rings) return b.vertex(c - Eigen::Vector3d(0, 0, r));
    const double th = M_PI * i / rings, ph = 2 * M_PI * (j % segments) / segments;
    return b.vertex(c + r * Eigen::Vector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int node = first_node + (4 * j) / segments;
      const int a = p(i, j), bb = p(i + 1, j), cc = p(i + 1, j + 1), d = p(i, j + 1);
      if (i != 0) b.face(a, bb, d, node);
      if (i != rings - 1) b.face(bb, cc, d, node);
    }
}

// A thin rectangular tube (a strut or an antenna rib: width x height cross-section [m]) bent
// along a quarter circle of radius r in the xy plane, `segments` segments, both ends capped,
// outward normals, node `node_id`.
inline void add_bent_tube(MeshBuilder& b, double r, double width, double height, int segments, int node_id) {
  auto corner = [&](int i, int k) {
    const double t = 0.5 * M_PI * i / segments;
    const Eigen::Vector3d radial(std::cos(t), std::sin(t), 0);
    const double dr = (k == 1 || k == 2) ? 0.5 * width : -0.5 * width;
    const double dz = (k >= 2) ? 0.5 * height : -0.5 * height;
    return b.vertex((r + dr) * radial + Eigen::Vector3d(0, 0, dz));
  };
  for (int i = 0; i < segments; ++i)
    for (int k = 0; k < 4; ++k) {
      // Side k joins corners k and k+1 of stations i and i+1 (quads split on one diagonal).
      const int a = corner(i, k), bb = corner(i, (k + 1) % 4), c = corner(i + 1, (k + 1) % 4), d = corner(i + 1, k);
      b.face(a, d, c, node_id);
      b.face(a, c, bb, node_id);
    }
  b.face(corner(0, 0), corner(0, 1), corner(0, 2), node_id);  // caps
  b.face(corner(0, 0), corner(0, 2), corner(0, 3), node_id);
  b.face(corner(segments, 0), corner(segments, 2), corner(segments, 1), node_id);
  b.face(corner(segments, 0), corner(segments, 3), corner(segments, 2), node_id);
}

// Two nodes side by side on a unit plate (node 0 for x < 0.5), n x n grid, open boundary.
inline Mesh two_node_plate(int n) {
  MeshBuilder b;
  b.grid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0, 1, 0), n, 0);
  b.grid(Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0, 1, 0), n, 1);
  return b.build(2);
}

// A stand-in for the sample satellite: a six-node box body, a four-node sphere (tank) and a
// two-sided solar panel (one node, back material 1) apart from the body.
inline Mesh satellite(int n_box, int rings) {
  MeshBuilder b;
  add_box(b, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 0.8, 1.2), n_box, true, 0);
  add_sphere(b, Eigen::Vector3d(0.5, 0.4, 2.0), 0.4, rings, 2 * rings, 6);
  b.grid(Eigen::Vector3d(1.5, 0, 0), Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(0, 0.8, 0), n_box, 10, 0, 1);
  Mesh m = b.build(11);
  m.material_names = {"white_paint", "solar_cell"};
  return m;
}

// Non-conforming: a coarse square (2 triangles, node 0) beside a 2x2-refined square (node 1):
// the coarse square's right edge meets three vertices of the fine one (a T-junction at its middle).
inline Mesh t_junction_mesh() {
  MeshBuilder b;
  const int a = b.raw_vertex({0, 0, 0}), bb = b.raw_vertex({1, 0, 0}), c = b.raw_vertex({1, 1, 0}),
            d = b.raw_vertex({0, 1, 0});
  b.face(a, bb, c, 0);
  b.face(a, c, d, 0);
  // Fine square [1,2]x[0,1]: its own copies of the shared corners (welding merges them).
  b.grid(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), 2, 1);
  return b.build(2);
}

// Non-manifold: a refined plate (node 0) with a fin (node 1) standing on its middle line, so the
// edges along x = 0.5 carry three or four faces, plus a bow-tie (two triangles sharing a vertex).
inline Mesh non_manifold_fin(int n) {
  MeshBuilder b;
  b.grid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), n, 0);
  b.grid(Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 0.5), n, 1);
  const int p = b.vertex({1, 1, 0});
  const int q = b.vertex({1.3, 1.1, 0}), r = b.vertex({1.1, 1.3, 0});
  const int s = b.vertex({1.3, 1.3, 0.2}), t = b.vertex({1.4, 1.2, 0.3});
  b.face(p, q, r, 2);
  b.face(p, s, t, 2);
  return b.build(3);
}

//! How many faces use each undirected edge (vertex pair, smaller index first): 2 on a
//! manifold interior edge, 1 on a rim, more on a non-manifold edge.
inline std::map<std::pair<int, int>, int> edge_counts(const Mesh& m) {
  std::map<std::pair<int, int>, int> e;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int j = 0; j < 3; ++j) {
      const int a = m.F(f, j), b = m.F(f, (j + 1) % 3);
      ++e[{std::min(a, b), std::max(a, b)}];
    }
  return e;
}

}  // namespace thermodec::test
