// The cost of a candidate collapse (Lindstrom-Turk: volume preservation and optimisation,
// boundary preservation, triangle shape), its validity (no flipped or degenerate face) and the
// per-node, per-region and per-part bookkeeping it would change. The cost is a float priority
// in vcg's heap, made scale-free by 1 / (bbox diagonal)^6.
//  P. Lindstrom, G. Turk, "Fast and memory efficient polygonal simplification", IEEE Vis 1998.
#include <algorithm>
#include <cmath>
#include <limits>

#include "node_collapse.h"

namespace thermodec::collapse {

void NodeCollapse::evaluate(Context& c, VVertex* gone, VVertex* kept, bool optimal) {
  valid_ = false;
  _priority = std::numeric_limits<float>::max();
  section_ = Section();
  pos.V(0) = gone;
  pos.V(1) = kept;
  removed_per_node_.clear();
  removed_per_region_.clear();
  area_delta_.clear();
  volume_delta_.clear();
  exact_per_node_.clear();

  const Vec3 pg = to_eigen(gone->cP()), pk = to_eigen(kept->cP());

  // Faces of the two stars (the removed ones are in both; list them once).
  auto& star_ = c.star;
  star_.clear();
  for (vcg::face::VFIterator<VFace> it(gone); !it.End(); ++it) star_.push_back(it.F());
  for (vcg::face::VFIterator<VFace> it(kept); !it.End(); ++it)
    if (it.V1() != gone && it.V2() != gone) star_.push_back(it.F());

  double boundary_cost = 0;
  bool straight = false;  // gone lies on a straight contour (free_exact_contour_collapses)
  if (!place(c, gone, kept, optimal, pg, pk, boundary_cost, straight)) return;

  // Validity (no flips, no degenerate faces) and cost. On a straight contour, also whether
  // each node's faces around `gone` are coplanar and keep their total area: then moving
  // `gone` onto `kept` (in the same plane, on the same line) re-triangulates the same
  // polygon and that node's geometry is unchanged.
  struct NodePlane {
    int node;
    Vec3 normal;
    bool coplanar;
    double area_before, area_after;
  };
  std::array<NodePlane, 4> planes;
  int nplanes = 0;
  auto plane_of = [&](int node, const Vec3& n0) -> NodePlane* {
    for (int i = 0; i < nplanes; ++i)
      if (planes[i].node == node) return &planes[i];
    if (nplanes == 4) return nullptr;
    const double len = n0.norm();
    planes[nplanes] = {node, len > 0 ? Vec3(n0 / len) : Vec3::Zero(), len > 0, 0.0, 0.0};
    return &planes[nplanes++];
  };
  double vol_cost = 0, vol_change = 0, shape = 0, mean_area2 = 0;
  for (VFace* f : star_) {
    const int fidx = c.fi(f);
    const int region = c.face_region[fidx], node = c.region_node[region];
    std::array<Vec3, 3> p, q;
    bool has_gone = false, has_kept = false;
    for (int j = 0; j < 3; ++j) {
      p[j] = to_eigen(f->cP(j));
      q[j] = p[j];
      if (f->cV(j) == gone) q[j] = x_, has_gone = true;
      if (f->cV(j) == kept) {
        has_kept = true;
        if (optimal) q[j] = x_;
      }
    }
    const Vec3 n0 = (p[1] - p[0]).cross(p[2] - p[0]);
    const double a0 = 0.5 * n0.norm();
    mean_area2 += a0;
    NodePlane* plane = nullptr;
    if (straight && has_gone) {
      plane = plane_of(node, n0);
      if (plane == nullptr) {
        straight = false;
      } else {
        const double len = n0.norm();
        if (!(len > 0) || (n0 / len - plane->normal).norm() > c.opt.exact_contour_tolerance) plane->coplanar = false;
        plane->area_before += a0;
      }
    }
    // LT volume terms: tetrahedron between the new vertex and the old face.
    const double tet = n0.dot(x_ - p[0]) / 6.0;
    vol_cost += tet * tet;
    vol_change += tet;
    if (has_gone && has_kept) {  // this face disappears
      removed_per_node_.add(node, 1.0);
      removed_per_region_.add(region, 1.0);
      area_delta_.add(node, -a0);
      volume_delta_.add(c.face_component[fidx], -p[0].dot(p[1].cross(p[2])) / 6.0);
      continue;
    }
    const Vec3 n1 = (q[1] - q[0]).cross(q[2] - q[0]);
    const double n1sq = n1.squaredNorm();
    if (n1sq <= c.degenerate_area2) return;
    if (n0.dot(n1) < c.cos_normal * std::sqrt(n0.squaredNorm() * n1sq)) return;
    area_delta_.add(node, 0.5 * std::sqrt(n1sq) - a0);
    if (plane != nullptr) plane->area_after += 0.5 * std::sqrt(n1sq);
    volume_delta_.add(c.face_component[fidx],
              (q[0].dot(q[1].cross(q[2])) - p[0].dot(p[1].cross(p[2]))) / 6.0);
    for (int j = 0; j < 3; ++j)
      if (f->cV(j) != gone && f->cV(j) != kept) shape += (q[j] - x_).squaredNorm();
  }
  if (removed_per_node_.empty()) return;  // not an edge of a face (cannot happen) -> skip
  if (removed_per_node_.overflow || removed_per_region_.overflow || area_delta_.overflow ||
      volume_delta_.overflow)
    return;
  if (straight)
    for (int i = 0; i < nplanes; ++i) {
      const NodePlane& p = planes[i];
      const bool exact = p.coplanar && std::abs(p.area_after - p.area_before) <=
                                           c.opt.exact_contour_tolerance * p.area_before;
      exact_per_node_.add(p.node, exact ? 1.0 : 0.0);
    }
  mean_area2 /= static_cast<double>(star_.size());
  mean_area2 *= mean_area2;
  const double cost = vol_cost + vol_change * vol_change + boundary_cost +
                      c.opt.shape_weight * shape * mean_area2;
  _priority = static_cast<ScalarType>(cost * c.cost_scale);
  valid_ = std::isfinite(_priority);
}

}  // namespace thermodec::collapse
