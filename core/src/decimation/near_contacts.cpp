// Near contacts of two nodes (DecimationOptions::near_contact_fraction).
//
// CAD assemblies place parts against each other without shared vertices: a hinge's end disc
// lies in the plane of the wall it is fixed to, millimetres in front of or behind it. The
// exchange across such a gap is decided at the gap's scale (which side of the wall a face
// lies on, which face a ray leaving the gap meets first), far below the mesh's edge lengths,
// so a collapse that moves a vertex there by a fraction of an edge moves the two nodes'
// radiative coupling at first order: measured on NPP_16, three collapses of a hinge embedded in
// a box wall 2-7 mm away raised the box's coupling to the hinge's node by 1.08 m^2 (4 %) and
// the box by +0.16 K, while every node-level criterion (area, projected area, reflected
// sunlight) held. Such vertices are frozen when one of their faces is nearly parallel to the
// other node's face (overlapping surfaces; a sheet standing across a panel only touches it
// along a line); the faces away from the contact still decimate.
#include "near_contacts.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include <Eigen/Geometry>

namespace thermodec::collapse {

namespace {

using Vec3 = Eigen::Vector3d;

// The largest gap [fraction of the bounding-box diagonal] still taken for a contact: NPP_16's
// hinge lies 2-7 mm off its wall in a 133 m box (5e-5); parts a few centimetres apart are not
// in contact and decimate freely (with 5 % of the shortest edge alone, NPP_16 froze 66 more
// faces than the hinge needs).
constexpr double kContactRelativeDistance = 1e-4;
// Faces within 10 degrees of parallel (either orientation) overlap at a contact.
constexpr double kParallelCos = 0.9848;

// Squared distance from p to the triangle (a, b, c) (closest point by Voronoi regions).
double squared_distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (ap - ab * (d1 / (d1 - d3))).squaredNorm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (ap - ac * (d2 / (d2 - d6))).squaredNorm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))).squaredNorm();
  const double denom = 1.0 / (va + vb + vc);
  return (ap - ab * (vb * denom) - ac * (vc * denom)).squaredNorm();
}

}  // namespace

std::vector<char> near_contact_vertices(const Mesh& mesh, double fraction) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  std::vector<char> near(nv, 0);
  if (!(fraction > 0) || nf == 0) return near;
  auto node_of = [&](int f) { return mesh.face_node.size() > f ? mesh.face_node[f] : -1; };
  // Per vertex: its reach (fraction x shortest edge) and whether its faces span several nodes.
  std::vector<double> reach(nv, std::numeric_limits<double>::infinity());
  std::vector<int> node(nv, std::numeric_limits<int>::min());  // the one node of its faces, or max() when several
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      const double e = (mesh.V.row(a) - mesh.V.row(b)).norm();
      reach[a] = std::min(reach[a], fraction * e);
      reach[b] = std::min(reach[b], fraction * e);
      int& n = node[a];
      n = n == std::numeric_limits<int>::min() || n == node_of(f) ? node_of(f) : std::numeric_limits<int>::max();
    }
  // A contact, not a gap: at most kContactRelativeDistance of the model's size.
  const Vec3 lo = mesh.V.colwise().minCoeff().transpose(), hi = mesh.V.colwise().maxCoeff().transpose();
  const double contact = kContactRelativeDistance * (hi - lo).norm();
  double max_reach = 0.0;
  for (int v = 0; v < nv; ++v)
    if (std::isfinite(reach[v])) max_reach = std::max(max_reach, reach[v] = std::min(reach[v], contact));
  if (!(max_reach > 0)) return near;
  // Unit normals of the faces and, per vertex, its faces (CSR): only a face of v nearly parallel
  // to the other node's face makes a contact whose exchange the gap decides (a hinge disc in its
  // wall's plane); a sheet standing across a panel touches it along a line that sees nothing.
  std::vector<Vec3> normal(static_cast<size_t>(nf), Vec3::Zero());
  std::vector<int> start(static_cast<size_t>(nv) + 1, 0), faces_at(3 * static_cast<size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    const Vec3 p0 = mesh.V.row(mesh.F(f, 0)).transpose(), p1 = mesh.V.row(mesh.F(f, 1)).transpose(),
               p2 = mesh.V.row(mesh.F(f, 2)).transpose();
    const Vec3 e = (p1 - p0).cross(p2 - p0);
    if (e.norm() > 0) normal[static_cast<size_t>(f)] = e.normalized();
    for (int k = 0; k < 3; ++k) ++start[static_cast<size_t>(mesh.F(f, k)) + 1];
  }
  for (int v = 0; v < nv; ++v) start[static_cast<size_t>(v) + 1] += start[static_cast<size_t>(v)];
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) faces_at[static_cast<size_t>(fill[static_cast<size_t>(mesh.F(f, k))]++)] = f;
  }
  auto parallel_face_at = [&](int v, const Vec3& n) {
    for (int i = start[static_cast<size_t>(v)]; i < start[static_cast<size_t>(v) + 1]; ++i)
      if (std::abs(normal[static_cast<size_t>(faces_at[static_cast<size_t>(i)])].dot(n)) >= kParallelCos) return true;
    return false;
  };
  // Vertices hashed into cubic cells; each face visits the cells its box (grown by the
  // largest reach) overlaps.
  const double cell = std::max({max_reach, (hi - lo).norm() / 128.0, 1e-12});
  auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
    return static_cast<std::uint64_t>((i * 73856093) ^ (j * 19349663) ^ (k * 83492791));
  };
  auto cell_of = [&](double x, double o) { return static_cast<std::int64_t>(std::floor((x - o) / cell)); };
  std::unordered_multimap<std::uint64_t, int> grid;
  grid.reserve(static_cast<size_t>(nv));
  for (int v = 0; v < nv; ++v)
    if (std::isfinite(reach[v]))
      grid.emplace(key(cell_of(mesh.V(v, 0), lo.x()), cell_of(mesh.V(v, 1), lo.y()), cell_of(mesh.V(v, 2), lo.z())), v);
  for (int f = 0; f < nf; ++f) {
    const Vec3 a = mesh.V.row(mesh.F(f, 0)).transpose(), b = mesh.V.row(mesh.F(f, 1)).transpose(),
               c = mesh.V.row(mesh.F(f, 2)).transpose();
    const Vec3 bmin = a.cwiseMin(b).cwiseMin(c).array() - max_reach, bmax = a.cwiseMax(b).cwiseMax(c).array() + max_reach;
    const int nf_node = node_of(f);
    for (std::int64_t i = cell_of(bmin.x(), lo.x()); i <= cell_of(bmax.x(), lo.x()); ++i)
      for (std::int64_t j = cell_of(bmin.y(), lo.y()); j <= cell_of(bmax.y(), lo.y()); ++j)
        for (std::int64_t k = cell_of(bmin.z(), lo.z()); k <= cell_of(bmax.z(), lo.z()); ++k) {
          const auto range = grid.equal_range(key(i, j, k));
          for (auto it = range.first; it != range.second; ++it) {
            const int v = it->second;
            if (near[v] || node[v] == nf_node) continue;  // already frozen, or all of v's faces are f's node
            if (mesh.F(f, 0) == v || mesh.F(f, 1) == v || mesh.F(f, 2) == v) continue;
            const Vec3 p = mesh.V.row(v).transpose();
            if ((p.array() < bmin.array()).any() || (p.array() > bmax.array()).any()) continue;
            if (squared_distance_to_triangle(p, a, b, c) <= reach[v] * reach[v] &&
                parallel_face_at(v, normal[static_cast<size_t>(f)]))
              near[v] = 1;
          }
        }
  }
  return near;
}

}  // namespace thermodec::collapse
