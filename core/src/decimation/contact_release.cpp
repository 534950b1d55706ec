// Contacts a flat surface need not carry as vertices. A sheet standing on a panel (a yoke on
// a body side: a non-manifold edge) or a part touching a flat face at one point (a dish on a
// boom's cap: a bow-tie vertex) makes the contact's vertices frozen, and a flat region that
// holds a frozen vertex inside it keeps two more faces per such vertex than its outline needs
// (a rectangle with two interior points needs 6 triangles, not 2). For the flat region the
// contact is a point on its plane: what it radiates, absorbs and sees (its outline, area and
// normal) is the same with or without a vertex there. So the region's faces get their own
// copy of the vertex, a free vertex inside a flat region whose collapses change nothing of its
// geometry; the touching part keeps the input vertex and it stays frozen, so the contact stays
// exactly where it was on the touching part and lies on the flat region's plane. The surfaces
// keep every face and no crack opens: the touching part rests on the flat region without
// sharing its vertices there (a T-contact instead of a shared edge).
#include "contact_release.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <tuple>

#include <Eigen/Geometry>

namespace thermodec::collapse {
namespace {

struct EdgeFace {
  int a, b, f, j;  // edge (a < b) is edge j of face f: F(f, j) -> F(f, j + 1)
  bool operator<(const EdgeFace& o) const { return std::tie(a, b, f, j) < std::tie(o.a, o.b, o.f, o.j); }
};

// For each face and edge j (F(f, j) -> F(f, j + 1)): the face it continues into across that
// edge, or -1. A manifold edge joins its two faces; a non-manifold edge joins only its one pair
// of coplanar, consistently oriented faces of one region (the surface a sheet stands on).
std::vector<std::array<int, 3>> continuations(const Mesh& mesh, const std::vector<int>& face_region,
                                              const std::vector<Eigen::Vector3d>& normal, double tol) {
  const int nf = mesh.num_faces();
  std::vector<EdgeFace> ef;
  ef.reserve(3 * nf);
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j) {
      const int a = mesh.F(f, j), b = mesh.F(f, (j + 1) % 3);
      ef.push_back({std::min(a, b), std::max(a, b), f, j});
    }
  std::sort(ef.begin(), ef.end());
  std::vector<std::array<int, 3>> next(nf, {-1, -1, -1});
  auto join = [&](const EdgeFace& p, const EdgeFace& q) {
    next[p.f][p.j] = q.f;
    next[q.f][q.j] = p.f;
  };
  for (size_t i = 0; i < ef.size();) {
    size_t k = i;
    while (k < ef.size() && ef[k].a == ef[i].a && ef[k].b == ef[i].b) ++k;
    if (k - i == 2) {
      join(ef[i], ef[i + 1]);
    } else if (k - i > 2) {
      int pairs = 0;
      std::pair<size_t, size_t> through{0, 0};
      for (size_t p = i; p < k; ++p)
        for (size_t q = p + 1; q < k; ++q) {
          const EdgeFace &x = ef[p], &y = ef[q];
          const bool opposite = mesh.F(x.f, x.j) == mesh.F(y.f, (y.j + 1) % 3);
          if (x.f != y.f && opposite && face_region[x.f] == face_region[y.f] && normal[x.f].norm() > 0 &&
              (normal[x.f] - normal[y.f]).norm() <= tol)
            ++pairs, through = {p, q};
        }
      if (pairs == 1) join(ef[through.first], ef[through.second]);
    }
    i = k;
  }
  return next;
}

}  // namespace

ContactRelease release_contacts(const Mesh& mesh, const std::vector<int>& face_region, double tol) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  ContactRelease out;
  out.mesh = mesh;
  out.input_vertex.resize(nv);
  std::iota(out.input_vertex.begin(), out.input_vertex.end(), 0);
  out.keep_frozen.assign(nv, 0);
  std::vector<Eigen::Vector3d> normal(nf);
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d p0 = mesh.V.row(mesh.F(f, 0)), p1 = mesh.V.row(mesh.F(f, 1)), p2 = mesh.V.row(mesh.F(f, 2));
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
    normal[f] = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
  }
  const auto next = continuations(mesh, face_region, normal, tol);
  std::vector<std::vector<int>> faces_at(nv);
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j) faces_at[mesh.F(f, j)].push_back(f);

  std::vector<int> root;
  std::vector<Eigen::Vector3d> extra;  // coordinates of the copies [m]
  for (int v = 0; v < nv; ++v) {
    const auto& fs = faces_at[v];
    if (fs.size() < 2) continue;
    // Fans: faces around v joined across the edges at v they continue into each other by.
    root.resize(fs.size());
    std::iota(root.begin(), root.end(), 0);
    auto find = [&root](int x) {
      while (root[x] != x) x = root[x] = root[root[x]];
      return x;
    };
    auto local = [&fs](int f) { return static_cast<int>(std::find(fs.begin(), fs.end(), f) - fs.begin()); };
    for (size_t p = 0; p < fs.size(); ++p)
      for (int j = 0; j < 3; ++j) {
        const int f = fs[p], g = next[f][j];
        const bool at_v = mesh.F(f, j) == v || mesh.F(f, (j + 1) % 3) == v;
        if (at_v && g >= 0) root[find(static_cast<int>(p))] = find(local(g));
      }
    std::vector<int> fans;
    for (size_t p = 0; p < fs.size(); ++p)
      if (find(static_cast<int>(p)) == static_cast<int>(p)) fans.push_back(static_cast<int>(p));
    if (fans.size() < 2) continue;
    // A fan is released when it closes around v, is one region and is flat.
    std::vector<int> released;
    for (int r : fans) {
      bool disk = true;
      int first = -1;
      for (size_t p = 0; p < fs.size() && disk; ++p) {
        if (find(static_cast<int>(p)) != r) continue;
        const int f = fs[p];
        if (first < 0) first = f;
        disk = face_region[f] == face_region[first] && normal[f].norm() > 0 && (normal[f] - normal[first]).norm() <= tol;
        for (int j = 0; j < 3 && disk; ++j)
          if (mesh.F(f, j) == v || mesh.F(f, (j + 1) % 3) == v) disk = next[f][j] >= 0;
      }
      if (disk) released.push_back(r);
    }
    if (released.size() == fans.size()) released.erase(released.begin());  // one fan keeps v
    for (int r : released) {
      const int copy = nv + static_cast<int>(extra.size());
      extra.push_back(mesh.V.row(v).transpose());
      out.input_vertex.push_back(v);
      out.keep_frozen.push_back(0);
      for (size_t p = 0; p < fs.size(); ++p)
        if (find(static_cast<int>(p)) == r)
          for (int j = 0; j < 3; ++j)
            if (out.mesh.F(fs[p], j) == v) out.mesh.F(fs[p], j) = copy;
    }
    if (!released.empty()) out.keep_frozen[v] = 1;
  }
  out.released = static_cast<int>(extra.size());
  if (!extra.empty()) {
    out.mesh.V.conservativeResize(nv + out.released, 3);
    for (int k = 0; k < out.released; ++k) out.mesh.V.row(nv + k) = extra[k].transpose();
  }
  return out;
}

}  // namespace thermodec::collapse
