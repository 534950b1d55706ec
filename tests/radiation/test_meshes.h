#pragma once
// Hand-built meshes for the radiation tests: rectangles, disks, spheres, boxes, with one node
// per part and every face one-sided unless said otherwise.
#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "thermodec/mesh/mesh.h"
#include "thermodec/nodes/thermal_model.h"

namespace thermodec::test {

//! Appends `part` to `mesh` as a new node named `name` (faces one-sided unless back >= 0).
inline void append_part(Mesh& mesh, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::string& name,
                        int back_material = -1) {
  const int v0 = mesh.num_vertices(), f0 = mesh.num_faces();
  const int node = static_cast<int>(mesh.node_names.size());
  mesh.node_names.push_back(name);
  if (mesh.material_names.empty()) mesh.material_names.push_back("default");
  Eigen::MatrixXd V2(v0 + V.rows(), 3);
  if (v0 > 0) V2.topRows(v0) = mesh.V;
  V2.bottomRows(V.rows()) = V;
  Eigen::MatrixXi F2(f0 + F.rows(), 3);
  if (f0 > 0) F2.topRows(f0) = mesh.F;
  F2.bottomRows(F.rows()) = (F.array() + v0).matrix();
  mesh.V = V2;
  mesh.F = F2;
  mesh.face_node.conservativeResize(f0 + F.rows());
  mesh.face_material.conservativeResize(f0 + F.rows());
  mesh.face_back_material.conservativeResize(f0 + F.rows());
  for (int f = f0; f < f0 + F.rows(); ++f) {
    mesh.face_node[f] = node;
    mesh.face_material[f] = 0;
    mesh.face_back_material[f] = back_material;
  }
}

//! Grid of n x m quads (2 triangles each) spanning corner + s*u + t*v, s,t in [0,1];
//! front normal = u x v.
inline void grid(const Eigen::Vector3d& corner, const Eigen::Vector3d& u, const Eigen::Vector3d& v, int n, int m,
                 Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
  V.resize((n + 1) * (m + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= m; ++j) V.row(i * (m + 1) + j) = corner + u * (double(i) / n) + v * (double(j) / m);
  F.resize(2 * n * m, 3);
  int f = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const int a = i * (m + 1) + j, b = (i + 1) * (m + 1) + j, c = (i + 1) * (m + 1) + j + 1, d = i * (m + 1) + j + 1;
      F.row(f++) << a, b, c;
      F.row(f++) << a, c, d;
    }
}

//! Disk of radius r at height z, normal +z (or -z if `down`), `rings` rings x `sectors`.
inline void disk(double r, double z, bool down, int rings, int sectors, Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
  V.resize(1 + rings * sectors, 3);
  V.row(0) << 0, 0, z;
  for (int i = 1; i <= rings; ++i)
    for (int k = 0; k < sectors; ++k) {
      const double rr = r * i / rings, a = 2 * M_PI * k / sectors;
      V.row(1 + (i - 1) * sectors + k) << rr * std::cos(a), rr * std::sin(a), z;
    }
  std::vector<Eigen::Vector3i> tris;
  for (int k = 0; k < sectors; ++k) tris.emplace_back(0, 1 + k, 1 + (k + 1) % sectors);
  for (int i = 1; i < rings; ++i)
    for (int k = 0; k < sectors; ++k) {
      const int a = 1 + (i - 1) * sectors + k, b = 1 + (i - 1) * sectors + (k + 1) % sectors;
      const int c = 1 + i * sectors + k, d = 1 + i * sectors + (k + 1) % sectors;
      tris.emplace_back(a, c, d);
      tris.emplace_back(a, d, b);
    }
  F.resize(tris.size(), 3);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    F.row(t) = tris[t].transpose();
    if (down) std::swap(F(t, 1), F(t, 2));
  }
}

//! UV sphere of radius r, normals outward (or inward if `inward`).
inline void sphere(double r, bool inward, int stacks, int slices, Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
  V.resize(2 + (stacks - 1) * slices, 3);
  V.row(0) << 0, 0, r;
  V.row(1) << 0, 0, -r;
  for (int i = 1; i < stacks; ++i)
    for (int k = 0; k < slices; ++k) {
      const double th = M_PI * i / stacks, ph = 2 * M_PI * k / slices;
      V.row(2 + (i - 1) * slices + k) << r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th);
    }
  auto idx = [&](int i, int k) { return 2 + (i - 1) * slices + (k % slices); };
  std::vector<Eigen::Vector3i> tris;
  for (int k = 0; k < slices; ++k) tris.emplace_back(0, idx(1, k), idx(1, k + 1));
  for (int i = 1; i < stacks - 1; ++i)
    for (int k = 0; k < slices; ++k) {
      tris.emplace_back(idx(i, k), idx(i + 1, k), idx(i + 1, k + 1));
      tris.emplace_back(idx(i, k), idx(i + 1, k + 1), idx(i, k + 1));
    }
  for (int k = 0; k < slices; ++k) tris.emplace_back(1, idx(stacks - 1, k + 1), idx(stacks - 1, k));
  F.resize(tris.size(), 3);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    F.row(t) = tris[t].transpose();
    if (inward) std::swap(F(t, 1), F(t, 2));
  }
}

//! Axis-aligned box [lo, hi], one node per box, normals outward (or inward), n x n per side.
inline void box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, bool inward, int n, Eigen::MatrixXd& V,
                Eigen::MatrixXi& F) {
  std::vector<Eigen::MatrixXd> Vs;
  std::vector<Eigen::MatrixXi> Fs;
  const Eigen::Vector3d d = hi - lo;
  const Eigen::Vector3d ex(d.x(), 0, 0), ey(0, d.y(), 0), ez(0, 0, d.z());
  auto side = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
    Eigen::MatrixXd Vi;
    Eigen::MatrixXi Fi;
    if (inward) grid(c, v, u, n, n, Vi, Fi); else grid(c, u, v, n, n, Vi, Fi);
    Vs.push_back(Vi);
    Fs.push_back(Fi);
  };
  side(lo, ey, ex);            // z = lo, normal -z
  side(lo + ez, ex, ey);       // z = hi, normal +z
  side(lo, ex, ez);            // y = lo, normal -y
  side(lo + ey, ez, ex);       // y = hi, normal +y
  side(lo, ez, ey);            // x = lo, normal -x
  side(lo + ex, ey, ez);       // x = hi, normal +x
  int nv = 0, nf = 0;
  for (std::size_t i = 0; i < Vs.size(); ++i) { nv += Vs[i].rows(); nf += Fs[i].rows(); }
  V.resize(nv, 3);
  F.resize(nf, 3);
  int ov = 0, of = 0;
  for (std::size_t i = 0; i < Vs.size(); ++i) {
    V.middleRows(ov, Vs[i].rows()) = Vs[i];
    F.middleRows(of, Fs[i].rows()) = (Fs[i].array() + ov).matrix();
    ov += Vs[i].rows();
    of += Fs[i].rows();
  }
}

//! A ThermalModel around `mesh` with one material (emissivity eps, absorptivity alpha) and
//! one node per mesh group.
inline ThermalModel model_of(const Mesh& mesh, double eps = 1.0, double alpha = 1.0, int rays = 4000,
                             std::uint64_t seed = 1) {
  ThermalModel m;
  m.mesh = mesh;
  m.materials.push_back(Material{"default", alpha, eps});
  for (const auto& n : mesh.node_names) m.nodes.push_back(Node{n, 0});
  m.radiation.rays_per_face = rays;
  m.radiation.seed = seed;
  return m;
}

}  // namespace thermodec::test
