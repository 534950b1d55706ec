// A candidate single-edge collapse: its placement, its validity (no flipped or degenerate
// face), the per-node, per-region and per-part bookkeeping it would change, and what it does
// to its star (StarChange), which collapse_cost() ranks.
#include <algorithm>
#include <cmath>
#include <limits>

#include "collapse_cost.h"
#include "node_collapse.h"

namespace thermodec::collapse {
namespace {

// On a straight contour: whether each node's faces around `gone` are coplanar and keep their
// total area. Then moving `gone` onto `kept` (in the same plane, on the same line)
// re-triangulates the same polygon and that node's geometry is unchanged.
struct NodePlanes {
  struct Plane {
    int node;
    Vec3 normal;
    bool coplanar;
    double area_before, area_after;
  };
  std::array<Plane, 4> planes;
  int n = 0;
  Plane* of(int node, const Vec3& n0) {
    for (int i = 0; i < n; ++i)
      if (planes[i].node == node) return &planes[i];
    if (n == 4) return nullptr;
    const double len = n0.norm();
    planes[n] = {node, len > 0 ? Vec3(n0 / len) : Vec3::Zero(), len > 0, 0.0, 0.0};
    return &planes[n++];
  }
};

}  // namespace

void NodeCollapse::reset(VVertex* gone, VVertex* kept) {
  valid_ = false;
  refused_ = CollapseBlock::none;
  _priority = std::numeric_limits<float>::max();
  section_ = Section();
  pos.V(0) = gone;
  pos.V(1) = kept;
  removed_per_node_.clear();
  removed_per_region_.clear();
  area_delta_.clear();
  volume_delta_.clear();
  sharp_delta_.clear();
  kink_m2_ = 0;
  wide_kink_ = false;
  exact_per_node_.clear();
  restore_ = Restoration();
}

void NodeCollapse::evaluate(Context& c, VVertex* gone, VVertex* kept, bool optimal) {
  reset(gone, kept);
  const Vec3 pg = to_eigen(gone->cP()), pk = to_eigen(kept->cP());

  // Faces of the two stars (the removed ones are in both; list them once).
  auto& star_ = c.star;
  star_.clear();
  for (vcg::face::VFIterator<VFace> it(gone); !it.End(); ++it) star_.push_back(it.F());
  for (vcg::face::VFIterator<VFace> it(kept); !it.End(); ++it)
    if (it.V1() != gone && it.V2() != gone) star_.push_back(it.F());

  StarChange& change = c.change;
  change.clear();
  bool straight = false;  // gone lies on a straight contour (free_exact_contour_collapses)
  if (!place(c, gone, kept, optimal, pg, pk, change.boundary_m6, straight)) return;  // place() says why

  NodePlanes planes;
  std::array<int, 4> kink_paid{};  // nodes charged for a kinked contour removal (each once)
  int nkink_paid = 0;
  for (VFace* f : star_) {
    const int fidx = c.fi(f);
    const int region = c.face_region[fidx], node = c.region_node[region];
    StarFaceChange fc;
    fc.node = node;
    bool has_gone = false, has_kept = false;
    for (int j = 0; j < 3; ++j) {
      fc.before[j] = to_eigen(f->cP(j));
      fc.after[j] = fc.before[j];
      if (f->cV(j) == gone) fc.after[j] = x_, has_gone = true;
      if (f->cV(j) == kept) {
        has_kept = true;
        if (optimal) fc.after[j] = x_;
      }
    }
    if (has_gone && kink_m2_ > 0 &&
        std::find(kink_paid.begin(), kink_paid.begin() + nkink_paid, node) == kink_paid.begin() + nkink_paid) {
      if (nkink_paid == 4) return set_refused(CollapseBlock::topology);
      // A wide kink: small against what the node's area may move, on a part small against the node.
      if (wide_kink_ && (kink_m2_ > c.opt.wide_kink_area_fraction * c.node_area_bound[node] * c.node_area0[node] ||
                         c.comp_area0[c.face_component[fidx]] > c.opt.wide_kink_part_fraction * c.node_area0[node]))
        return set_refused(CollapseBlock::contour_deviation);
      kink_paid[nkink_paid++] = node;
      sharp_delta_.add(node, kink_m2_);
    }
    const auto& p = fc.before;
    const auto& q = fc.after;
    const Vec3 n0 = (p[1] - p[0]).cross(p[2] - p[0]);
    const double a0 = 0.5 * n0.norm();
    change.star_area_m2 += a0;
    NodePlanes::Plane* plane = nullptr;
    if (straight && has_gone) {
      plane = planes.of(node, n0);
      if (plane == nullptr) {
        straight = false;
      } else {
        const double len = n0.norm();
        if (!(len > 0) || (n0 / len - plane->normal).norm() > c.opt.exact_contour_tolerance) plane->coplanar = false;
        plane->area_before += a0;
      }
    }
    // LT volume terms: tetrahedron between the new vertex and the old face.
    fc.swept_m3 = n0.dot(x_ - p[0]) / 6.0;
    if (has_gone && has_kept) {  // this face disappears
      fc.removed = true;
      removed_per_node_.add(node, 1.0);
      removed_per_region_.add(region, 1.0);
      area_delta_.add(node, -a0);
      volume_delta_.add(c.face_component[fidx], -p[0].dot(p[1].cross(p[2])) / 6.0);
      change.faces.push_back(fc);
      continue;
    }
    const Vec3 n1 = (q[1] - q[0]).cross(q[2] - q[0]);
    const double n1sq = n1.squaredNorm();
    double steep_m2 = 0;
    if (!c.turn_allowed(n0, n1, steep_m2)) return set_refused(CollapseBlock::normal_deviation);
    if (steep_m2 > 0) sharp_delta_.add(node, steep_m2);
    area_delta_.add(node, 0.5 * std::sqrt(n1sq) - a0);
    if (plane != nullptr) plane->area_after += 0.5 * std::sqrt(n1sq);
    volume_delta_.add(c.face_component[fidx], (q[0].dot(q[1].cross(q[2])) - p[0].dot(p[1].cross(p[2]))) / 6.0);
    for (int j = 0; j < 3; ++j)
      if (f->cV(j) != gone && f->cV(j) != kept) change.shape_m2 += (q[j] - x_).squaredNorm();
    change.faces.push_back(fc);
  }
  change.star_faces = static_cast<int>(star_.size());
  if (removed_per_node_.empty() || removed_per_node_.overflow || removed_per_region_.overflow ||
      area_delta_.overflow || volume_delta_.overflow || sharp_delta_.overflow)
    return set_refused(CollapseBlock::topology);  // not an edge of a face, or > 4 regions around it
  if (straight)
    for (int i = 0; i < planes.n; ++i) {
      const auto& p = planes.planes[i];
      const bool exact =
          p.coplanar && std::abs(p.area_after - p.area_before) <= c.opt.exact_contour_tolerance * p.area_before;
      exact_per_node_.add(p.node, exact ? 1.0 : 0.0);
    }
  _priority = static_cast<ScalarType>(collapse_cost(c, change));
  valid_ = std::isfinite(_priority);
}

}  // namespace thermodec::collapse
