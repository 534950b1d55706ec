// Node-area restoration (DecimationOptions::restore_node_areas): a collapse that would take a
// node's area past its bound runs when the node's free vertices, each moved along its own area
// gradient by a common fraction of its shortest edge, bring the area back to its input value.
// Planned exactly on the geometry after the collapse (the collapse's faces with its vertex at
// x_), before the collapse is accepted, so the bounds hold whatever is decided.
#include <algorithm>
#include <cmath>
#include <limits>

#include "node_collapse.h"

namespace thermodec::collapse {
namespace {

// One restoring vertex: where it is after the collapse [m], its offset direction (its area
// gradient's unit vector times its shortest edge) [m], and its area gradient [m].
struct Mover {
  VVertex* v;
  Vec3 p, dir, grad;
  double shortest;
};

Vec3 area_vector(const std::array<Vec3, 3>& p) { return 0.5 * (p[1] - p[0]).cross(p[2] - p[0]); }

}  // namespace

bool NodeCollapse::plan_area_restoration(Context& c, int node) {
  restore_ = Restoration();
  if (!c.opt.restore_node_areas || c.node_projection_change.empty() || section_.n > 0) return false;
  const VVertex* gone = pos.cV(0);
  const VVertex* kept = pos.cV(1);
  // The node's faces after the collapse (corners), and the free vertices that may move.
  std::vector<std::array<Vec3, 3>> faces;
  std::vector<std::array<int, 3>> slots;  // per face corner: mover index or -1
  std::vector<Mover> movers;
  std::array<Vec3, 3> q;
  for (int f : c.group_faces[node]) {
    const VFace& face = c.m->face[f];
    if (face.IsD()) continue;
    int j = -1;
    if (corners_after(&face, x_, q, j) == 2) continue;  // disappears with the collapse
    std::array<int, 3> s{-1, -1, -1};
    for (int k = 0; k < 3; ++k) {
      VVertex* v = face.cV(k);
      if (v == gone || v == kept || c.vclass[c.vi(v)] != kFree) continue;
      int& slot = c.restore_slot[c.vi(v)];
      if (slot < 0) {
        slot = static_cast<int>(movers.size());
        movers.push_back({v, q[k], Vec3::Zero(), Vec3::Zero(), std::numeric_limits<double>::infinity()});
      }
      s[k] = slot;
    }
    faces.push_back(q);
    slots.push_back(s);
  }
  for (const Mover& mv : movers) c.restore_slot[c.vi(mv.v)] = -1;
  // Area gradients and shortest edges of the movers, the node's area after the collapse.
  double area0 = 0;
  for (size_t i = 0; i < faces.size(); ++i) {
    const auto& p = faces[i];
    const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double len = n.norm();
    area0 += 0.5 * len;
    for (int k = 0; k < 3; ++k) {
      if (slots[i][k] < 0) continue;
      Mover& mv = movers[slots[i][k]];
      const Vec3 &b = p[(k + 1) % 3], &d = p[(k + 2) % 3];
      if (len > 0) mv.grad += 0.5 * (b - d).cross(n / len);
      mv.shortest = std::min({mv.shortest, (b - p[k]).norm(), (d - p[k]).norm()});
    }
  }
  double slope = 0;  // d area / d s [m^2]
  for (Mover& mv : movers) {
    const double g = mv.grad.norm();
    if (!(g > 1e-9 * mv.shortest) || !std::isfinite(mv.shortest)) continue;  // flat around it: no use
    mv.dir = mv.shortest * mv.grad / g;
    slope += mv.shortest * g;
  }
  const double target = c.node_area0[node];
  if (!(slope > 0)) return false;
  // Chord-Newton on s (the slope at s = 0), exact area at each step.
  auto area_at = [&](double s, std::vector<std::array<Vec3, 3>>* out) {
    double a = 0;
    for (size_t i = 0; i < faces.size(); ++i) {
      std::array<Vec3, 3> p = faces[i];
      for (int k = 0; k < 3; ++k)
        if (slots[i][k] >= 0) p[k] += s * movers[slots[i][k]].dir;
      a += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
      if (out != nullptr) (*out)[i] = p;
    }
    return a;
  };
  const double tolerance = 1e-3 * c.node_area_bound[node] * target;
  double s = 0, area = area0;
  for (int it = 0; it < 8 && std::abs(area - target) > tolerance; ++it) {
    s += (target - area) / slope;
    if (!(std::abs(s) <= c.opt.max_restoring_offset)) return false;
    area = area_at(s, nullptr);
  }
  if (!c.area_within_bound(node, area - c.node_area[node])) return false;
  // Turns, degenerate faces and closed volumes of the restored node.
  std::vector<std::array<Vec3, 3>> moved(faces.size());
  area_at(s, &moved);
  Deltas volume;
  int face_index = 0;
  for (int f : c.group_faces[node]) {
    const VFace& face = c.m->face[f];
    if (face.IsD()) continue;
    int j = -1;
    if (corners_after(&face, x_, q, j) == 2) continue;
    const auto& p = faces[face_index];
    const auto& r = moved[face_index++];
    const Vec3 n0 = (p[1] - p[0]).cross(p[2] - p[0]), n1 = (r[1] - r[0]).cross(r[2] - r[0]);
    const double n1sq = n1.squaredNorm();
    if (n1sq <= c.degenerate_area2 || n0.dot(n1) < c.cos_normal * std::sqrt(n0.squaredNorm() * n1sq)) return false;
    volume.add(c.face_component[f], (r[0].dot(r[1].cross(r[2])) - p[0].dot(p[1].cross(p[2]))) / 6.0);
  }
  if (volume.overflow) return false;
  // Radiatively, the restored node must stay within its projected-area cap in every direction
  // (all collapses so far, this one and the restoration).
  Context::Projection dp = c.node_projection_change[node];
  add_projection_change(c, node, dp);
  Context::Projection restoring{};
  for (size_t i = 0; i < faces.size(); ++i) add_projection(area_vector(faces[i]), area_vector(moved[i]), restoring);
  const double cap = c.projection_cap_m2(node);
  for (int k = 0; k < Context::kProjectionDirections; ++k)
    if (!(std::abs(dp[k] + restoring[k]) <= cap)) return false;
  restore_.projection.assign(restoring.begin(), restoring.end());
  restore_.node = node;
  restore_.area_m2 = area - area0;
  restore_.volume = volume;
  for (const Mover& mv : movers)
    if (mv.dir.squaredNorm() > 0) restore_.moves.emplace_back(mv.v, mv.p + s * mv.dir);
  return true;
}

void NodeCollapse::apply_area_restoration(Context& c) {
  if (restore_.node < 0) return;
  // UpdateHeap stamps the kept vertex's star with the next clock value; the restored stars
  // get the same, so every queued collapse around them is re-evaluated when it surfaces.
  for (const auto& [v, p] : restore_.moves) {
    v->P() = vcg::Point3d(p[0], p[1], p[2]);
    c.stamp[c.vi(v)] = c.clock + 1;
    for (vcg::face::VFIterator<VFace> it(v); !it.End(); ++it) {
      c.stamp[c.vi(it.V1())] = c.clock + 1;
      c.stamp[c.vi(it.V2())] = c.clock + 1;
    }
  }
  c.node_area[restore_.node] += restore_.area_m2;
  for (int k = 0; k < Context::kProjectionDirections; ++k)
    c.node_projection_change[restore_.node][k] += restore_.projection[k];
  for (const auto& d : restore_.volume) c.comp_volume[d.key] += d.value;
}

}  // namespace thermodec::collapse
