#include "thermodec/rays/coincident_faces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <tuple>

namespace thermodec::detail {

namespace {
struct PlaneFace {
  std::array<Eigen::Vector3d, 3> v;
  Eigen::AlignedBox3d box;
  Eigen::Vector3d m;  // unit normal, sign fixed by its largest component (planes, not sides)
  double d = 0.0;     // m . v[0]
  bool valid = false;
};

// Positive-area overlap of two triangles in the plane of `m`: no separating axis among the
// six in-plane edge normals, with a margin `eps` [m] (touching edges and corners separate).
bool overlap_in_plane(const PlaneFace& a, const PlaneFace& b, double eps) {
  for (const PlaneFace* t : {&a, &b})
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d axis = t->m.cross(t->v[(k + 1) % 3] - t->v[k]);
      const double len = axis.norm();
      if (len == 0.0) continue;
      double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
      for (const auto& p : a.v) amin = std::min(amin, axis.dot(p)), amax = std::max(amax, axis.dot(p));
      for (const auto& p : b.v) bmin = std::min(bmin, axis.dot(p)), bmax = std::max(bmax, axis.dot(p));
      if (amax <= bmin + eps * len || bmax <= amin + eps * len) return false;
    }
  return true;
}
}  // namespace

CoincidentPrims coincident_prims(const RayScene::Impl& scene) {
  const int P = static_cast<int>(scene.face_of_prim.size());
  const Mesh& mesh = scene.mesh;
  const double size = std::max(1e-9, scene.bounds.isEmpty() ? 1.0 : scene.bounds.diagonal().norm());
  const double tol = 1e-6 * size;
  std::vector<PlaneFace> faces(P);
  // Buckets by plane, coarse (1e-4) so that faces coplanar to rounding share one; the offset's
  // neighbouring buckets are looked up too.
  using Key = std::tuple<long, long, long, long>;
  std::map<Key, std::vector<int>> buckets;
  std::vector<Key> key(P);
  for (int p = 0; p < P; ++p) {
    PlaneFace& f = faces[p];
    const int face = scene.face_of_prim[p];
    for (int k = 0; k < 3; ++k) f.box.extend(f.v[k] = mesh.V.row(mesh.F(face, k)).transpose());
    const Eigen::Vector3d n = (f.v[1] - f.v[0]).cross(f.v[2] - f.v[0]);
    if (!(n.norm() > 0.0)) continue;
    f.m = n.normalized();
    Eigen::Index i;
    f.m.cwiseAbs().maxCoeff(&i);
    if (f.m[i] < 0.0) f.m = -f.m;
    f.d = f.m.dot(f.v[0]);
    f.valid = true;
    key[p] = Key(std::lround(f.m.x() * 1e4), std::lround(f.m.y() * 1e4), std::lround(f.m.z() * 1e4),
                 std::lround(f.d / (1e-4 * size)));
    buckets[key[p]].push_back(p);
  }
  std::vector<std::vector<int>> partners(P);
  for (int p = 0; p < P; ++p) {
    if (!faces[p].valid) continue;
    const PlaneFace& a = faces[p];
    for (long dd = -1; dd <= 1; ++dd) {
      Key k = key[p];
      std::get<3>(k) += dd;
      const auto it = buckets.find(k);
      if (it == buckets.end()) continue;
      for (int q : it->second) {
        if (q == p) continue;
        const PlaneFace& b = faces[q];
        if ((a.box.min() - b.box.max()).maxCoeff() > tol || (b.box.min() - a.box.max()).maxCoeff() > tol) continue;
        if (std::abs(a.m.dot(b.m)) < 1.0 - 1e-9) continue;
        bool in_plane = true;
        for (const auto& v : b.v) in_plane &= std::abs(a.m.dot(v) - a.d) <= tol;
        for (const auto& v : a.v) in_plane &= std::abs(b.m.dot(v) - b.d) <= tol;
        if (in_plane && overlap_in_plane(a, b, tol)) partners[p].push_back(q);
      }
    }
  }
  CoincidentPrims out;
  out.begin.assign(P + 1, 0);
  for (int p = 0; p < P; ++p) out.begin[p + 1] = out.begin[p] + static_cast<int>(partners[p].size());
  out.list.reserve(out.begin[P]);
  for (int p = 0; p < P; ++p) {
    std::sort(partners[p].begin(), partners[p].end());
    out.list.insert(out.list.end(), partners[p].begin(), partners[p].end());
  }
  return out;
}

}  // namespace thermodec::detail
