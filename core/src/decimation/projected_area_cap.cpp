// The projected-area cap (DecimationOptions::projected_area_cap): each node's projected area
// P(d) = sum_f max(0, N_f . d) (N_f a face's area vector) is tracked in 64 directions over all
// the collapses that touch it, and a collapse runs only if every node it touches stays within
// its cap in every direction. Distant exchange (the Sun, the planet, far nodes) sees a node
// through P; what a collapse does to it is measured here, not bounded from its faces' turns.
#include <algorithm>
#include <cmath>

#include "node_collapse.h"

namespace thermodec::collapse {

const std::array<Vec3, Context::kProjectionDirections>& Context::projection_directions() {
  static const std::array<Vec3, kProjectionDirections> dirs = [] {
    std::array<Vec3, kProjectionDirections> d;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int k = 0; k < kProjectionDirections; ++k) {
      const double z = 1.0 - (2.0 * k + 1.0) / kProjectionDirections, r = std::sqrt(1.0 - z * z);
      d[k] = Vec3(r * std::cos(golden * k), r * std::sin(golden * k), z);
    }
    return d;
  }();
  return dirs;
}

void add_projection(const Vec3& n0, const Vec3& n1, Context::Projection& dp) {
  const auto& dirs = Context::projection_directions();
  for (int k = 0; k < Context::kProjectionDirections; ++k)
    dp[k] += std::max(0.0, n1.dot(dirs[k])) - std::max(0.0, n0.dot(dirs[k]));
}

void NodeCollapse::gather_faces_around_moved_vertices(Context& c) const {
  auto& faces = c.projection_faces;
  faces.clear();
  auto around = [&](VVertex* v) {
    for (vcg::face::VFIterator<VFace> it(v); !it.End(); ++it) faces.push_back(it.F());
  };
  if (section_.n > 0) {
    for (int j = 0; j < section_.n; ++j) around(section_.gone[j]), around(section_.kept[j]);
  } else {
    around(const_cast<VVertex*>(pos.cV(0))), around(const_cast<VVertex*>(pos.cV(1)));
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
}

void NodeCollapse::corners_before_after(const VFace* f, std::array<Vec3, 3>& p, std::array<Vec3, 3>& q) const {
  int moved_at = -1;
  if (section_.n > 0)
    for (int k = 0; k < 3; ++k) q[k] = section_position(f->cV(k), section_.shift);
  else
    corners_after(f, x_, q, moved_at);
  for (int k = 0; k < 3; ++k) p[k] = to_eigen(f->cP(k));
}

void NodeCollapse::add_projection_change(Context& c, int node, Context::Projection& dp) const {
  // The faces around every vertex that moves or goes (removed faces collapse to zero area).
  gather_faces_around_moved_vertices(c);
  const auto& faces = c.projection_faces;
  std::array<Vec3, 3> p, q;
  for (const VFace* f : faces) {
    if (c.region_node[c.face_region[c.fi(f)]] != node) continue;
    corners_before_after(f, p, q);
    add_projection(0.5 * (p[1] - p[0]).cross(p[2] - p[0]), 0.5 * (q[1] - q[0]).cross(q[2] - q[0]), dp);
  }
}

bool NodeCollapse::projection_within_cap(Context& c, int node) const {
  Context::Projection dp = c.node_projection_change[node];
  add_projection_change(c, node, dp);
  const bool restored = node == restore_.node && !restore_.projection.empty();
  const double cap = c.projection_cap_m2(node);
  for (int k = 0; k < Context::kProjectionDirections; ++k)
    if (!(std::abs(dp[k] + (restored ? restore_.projection[k] : 0.0)) <= cap)) return false;
  return true;
}

void NodeCollapse::record_projection_change(Context& c) const {
  if (c.node_projection_change.empty()) return;
  for (const auto& d : area_delta_) add_projection_change(c, d.key, c.node_projection_change[d.key]);
}

}  // namespace thermodec::collapse
