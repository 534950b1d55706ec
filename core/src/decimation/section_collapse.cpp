// Thin-tube section collapse. CAD struts, antenna ribs, booms and cables are tubes of a few
// long segments around a thin cross-section (tdrs: 2 m segments of a 0.23 m x 0.04 m rib). A
// single edge collapse drags one corner of a cross-section a whole segment along the tube:
// on a curved tube the thin side faces then span the chord's sagitta across their small width
// and turn by tens of degrees (refused by the normal test), on a straight one the tube is
// skewed. Removing a whole cross-section loop at once keeps the tube a tube: each side face
// follows the chord between the remaining loops and turns by about half the axis' bend.
//
// The chord is shorter than the arc it replaces, so the tube loses area and volume; the kept
// loop moves out of the bend until the collapse leaves both unchanged, in the spirit of
// area-neutral placement for single collapses (vertex_placement.cpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "collapse_cost.h"
#include "node_collapse.h"

namespace thermodec::collapse {
namespace {

using Loop = std::array<VVertex*, NodeCollapse::kMaxSection>;

// Distinct neighbours of v (vertices sharing a face with it), in pointer order.
void vertex_neighbours(VVertex* v, std::vector<VVertex*>& out) {
  out.clear();
  for (vcg::face::VFIterator<VFace> it(v); !it.End(); ++it) {
    out.push_back(it.V1());
    out.push_back(it.V2());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

bool adjacent(VVertex* a, VVertex* b) {
  for (vcg::face::VFIterator<VFace> it(a); !it.End(); ++it)
    if (it.V1() == b || it.V2() == b) return true;
  return false;
}

int index_in(const Loop& loop, int n, const VVertex* v) {
  for (int j = 0; j < n; ++j)
    if (loop[j] == v) return j;
  return -1;
}

// The loop of short edges (squared length below max_len2 [m^2]) through v, in cycle order from
// v: its length n >= 3, or 0 if some vertex on it has other than two short edges (an end cap,
// a junction, an ordinary surface) or the loop is longer than kMaxSection.
int short_loop(VVertex* v, double max_len2, Loop& loop, std::vector<VVertex*>& scratch) {
  VVertex* nb[2];
  auto short_neighbours = [&](VVertex* x) {
    vertex_neighbours(x, scratch);
    int k = 0;
    for (VVertex* w : scratch)
      if ((to_eigen(w->cP()) - to_eigen(x->cP())).squaredNorm() < max_len2) {
        if (k == 2) return 3;
        nb[k++] = w;
      }
    return k;
  };
  if (short_neighbours(v) != 2) return 0;
  int n = 0;
  loop[n++] = v;
  VVertex* prev = v;
  VVertex* cur = nb[0];
  while (cur != v) {
    if (n == NodeCollapse::kMaxSection) return 0;
    loop[n++] = cur;
    if (short_neighbours(cur) != 2 || (nb[0] != prev && nb[1] != prev)) return 0;
    VVertex* next = nb[0] == prev ? nb[1] : nb[0];
    prev = cur;
    cur = next;
  }
  return n >= 3 ? n : 0;
}

}  // namespace

bool NodeCollapse::on_thin_tube(Context& c, VVertex* v, VVertex* w) {
  const double len2 = (to_eigen(v->cP()) - to_eigen(w->cP())).squaredNorm();
  Loop loop;
  const int n = short_loop(v, c.opt.tube_section_ratio * c.opt.tube_section_ratio * len2, loop, c.section_scratch[0]);
  for (int j = 0; j < n; ++j)
    if (c.vclass[c.vi(loop[j])] != kFree) return false;  // only single collapses can coarsen it
  return n > 0;
}

bool NodeCollapse::find_section(Context& c, VVertex* gone, VVertex* kept, Section& s) {
  const double axial2 = (to_eigen(gone->cP()) - to_eigen(kept->cP())).squaredNorm();
  const double max_len2 = c.opt.tube_section_ratio * c.opt.tube_section_ratio * axial2;
  const int n = short_loop(gone, max_len2, s.gone, c.section_scratch[0]);
  if (n == 0) return false;
  Loop k;
  if (short_loop(kept, max_len2, k, c.section_scratch[0]) != n) return false;
  for (int j = 0; j < n; ++j)
    if (c.vclass[c.vi(s.gone[j])] != kFree || index_in(k, n, s.gone[j]) >= 0) return false;
  // k[0] is `kept`; walk the kept loop in the direction where every pair shares an edge.
  for (const int dir : {1, n - 1}) {
    bool aligned = true;
    for (int j = 0; j < n && aligned; ++j) {
      s.kept[j] = k[(dir * j) % n];
      aligned = adjacent(s.gone[j], s.kept[j]);
    }
    if (aligned) {
      s.n = n;
      return true;
    }
  }
  return false;
}

// Topology: the faces around the gone loop are the 2n faces between the two loops (removed)
// and faces with a corner off both loops (moved onto the kept loop). A cap (a face on the gone
// loop only), a face joining the kept loop to a third vertex, or an outer vertex already
// adjacent to the kept loop would make the collapse fold or duplicate faces: refused.
bool NodeCollapse::section_topology_ok(Context& c) const {
  const Section& s = section_;
  const int n = s.n;
  auto& outer = c.section_scratch[1];
  outer.clear();
  int removed = 0;
  for (VFace* f : c.star) {
    int on_gone = 0, on_kept = 0, off = 0;
    for (int j = 0; j < 3; ++j) {
      VVertex* v = f->V(j);
      if (index_in(s.gone, n, v) >= 0)
        ++on_gone;
      else if (index_in(s.kept, n, v) >= 0)
        ++on_kept;
      else
        ++off;
    }
    if (on_gone == 0) continue;  // a face around the kept loop only (moved, never removed)
    for (int j = 0; j < 3; ++j)
      if (index_in(s.gone, n, f->V(j)) < 0 && index_in(s.kept, n, f->V(j)) < 0) outer.push_back(f->V(j));
    if (off > 0 && on_kept > 0) return false;
    if (off == 0) {
      if (on_kept == 0) return false;  // a cap
      // Between the loops: after the merge two corners must coincide, else it would survive as
      // a face of the kept loop alone.
      if (!section_removes(f)) return false;
      ++removed;
    }
  }
  if (removed != 2 * n) return false;
  std::sort(outer.begin(), outer.end());
  outer.erase(std::unique(outer.begin(), outer.end()), outer.end());
  for (VVertex* o : outer)
    for (vcg::face::VFIterator<VFace> it(o); !it.End(); ++it)
      if (index_in(s.kept, n, it.V1()) >= 0 || index_in(s.kept, n, it.V2()) >= 0) return false;
  return true;
}

Vec3 NodeCollapse::section_position(const VVertex* v, const Vec3& shift) const {
  const Section& s = section_;
  int j = index_in(s.gone, s.n, v);
  if (j < 0) j = index_in(s.kept, s.n, v);
  if (j < 0) return to_eigen(v->cP());
  const Vec3 p = to_eigen(s.kept[j]->cP());
  return shift.isZero() ? p : Vec3(p + shift);
}

// Area [m^2] of c.star after the collapse with the kept loop moved by `shift`, and the change
// of the enclosed volume [m^3], with their gradients with respect to that shift: for a
// triangle (x, b, d), d area / dx = (b - d) x n / 2 with n its unit normal and
// d volume / dx = (b x d) / 6, summed over the corners on the kept loop.
NodeCollapse::SectionMeasures NodeCollapse::section_measures(const Context& c, const Vec3& shift) const {
  SectionMeasures m;
  for (const VFace* f : c.star) {
    std::array<Vec3, 3> p, q;
    for (int j = 0; j < 3; ++j) p[j] = to_eigen(f->cP(j)), q[j] = section_position(f->cV(j), shift);
    const Vec3 n = (q[1] - q[0]).cross(q[2] - q[0]);
    const double len = n.norm();
    m.area_m2 += 0.5 * len;  // removed faces have collapsed to zero area
    m.volume_change_m3 += (q[0].dot(q[1].cross(q[2])) - p[0].dot(p[1].cross(p[2]))) / 6.0;
    for (int j = 0; j < 3; ++j) {
      if (index_in(section_.gone, section_.n, f->cV(j)) < 0 && index_in(section_.kept, section_.n, f->cV(j)) < 0)
        continue;
      const Vec3& b = q[(j + 1) % 3];
      const Vec3& d = q[(j + 2) % 3];
      if (len > 0) m.area_gradient += 0.5 * (b - d).cross(n / len);
      m.volume_gradient += b.cross(d) / 6.0;
    }
  }
  return m;
}

// Shift of the kept loop [m] that restores what the chord cut off. On a bent tube the area's
// and the volume's gradients point out of the bend, so moving the loop that way lengthens the
// tube back towards the arc. Tried in turn, the first within a quarter of the collapsed edge's
// length (and the closed part's volume bound) wins: the collapse leaves both the node's area and
// the closed part's volume unchanged (minimum-norm Newton steps on the two conditions), or the
// node's area alone. Zero if neither, or if a kept vertex may not move.
Vec3 NodeCollapse::section_restoring_shift(const Context& c) const {
  const Section& s = section_;
  for (int j = 0; j < s.n; ++j)
    if (c.vclass[c.vi(s.kept[j])] != kFree) return Vec3::Zero();
  double before = 0;  // area of the star before the collapse [m^2]
  for (const VFace* f : c.star) {
    const Vec3 p0 = to_eigen(f->cP(0)), p1 = to_eigen(f->cP(1)), p2 = to_eigen(f->cP(2));
    before += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  const double max_move = 0.25 * (to_eigen(s.gone[0]->cP()) - to_eigen(s.kept[0]->cP())).norm();
  const int comp = c.face_component[c.fi(c.star.front())];
  for (const bool with_volume : {true, false}) {
    if (with_volume && !c.comp_closed[comp]) continue;
    Vec3 shift = Vec3::Zero();
    bool converged = false;
    for (int it = 0; it < 8 && !converged; ++it) {
      const SectionMeasures m = section_measures(c, shift);
      const double ra = before - m.area_m2, rv = -m.volume_change_m3;
      converged = std::abs(ra) <= 1e-12 * before &&
                  (!with_volume || std::abs(rv) <= 1e-9 * std::abs(c.comp_volume0[comp]));
      if (converged) break;
      if (with_volume) {
        Eigen::Matrix<double, 2, 3> jac;
        jac.row(0) = m.area_gradient.transpose();
        jac.row(1) = m.volume_gradient.transpose();
        const Eigen::Matrix2d jjt = jac * jac.transpose();
        if (!(std::abs(jjt.determinant()) > 1e-12 * jjt.squaredNorm())) break;
        shift += jac.transpose() * jjt.inverse() * Eigen::Vector2d(ra, rv);
      } else {
        const double g2 = m.area_gradient.squaredNorm();
        if (!(g2 > 0)) break;
        shift += (ra / g2) * m.area_gradient;
      }
      if (!(shift.norm() <= max_move)) break;
    }
    if (converged && shift.norm() <= max_move && section_keeps_volume(c, shift)) return shift;
  }
  return Vec3::Zero();
}

bool NodeCollapse::section_keeps_volume(const Context& c, const Vec3& shift) const {
  const int comp = c.face_component[c.fi(c.star.front())];
  if (!c.comp_closed[comp]) return true;
  return c.volume_within_bound(comp, section_measures(c, shift).volume_change_m3);
}

bool NodeCollapse::evaluate_section(Context& c, VVertex* gone, VVertex* kept) {
  reset(gone, kept);
  if (!find_section(c, gone, kept, section_)) return false;
  Section& s = section_;
  // The faces around both loops, each once.
  auto& star = c.star;
  star.clear();
  for (int j = 0; j < s.n; ++j)
    for (VVertex* v : {s.gone[j], s.kept[j]})
      for (vcg::face::VFIterator<VFace> it(v); !it.End(); ++it) star.push_back(it.F());
  std::sort(star.begin(), star.end());
  star.erase(std::unique(star.begin(), star.end()), star.end());
  if (!section_topology_ok(c)) return section_.n = 0, set_refused(CollapseBlock::topology), false;
  s.centre.setZero();
  for (int j = 0; j < s.n; ++j) s.centre += to_eigen(s.kept[j]->cP());
  s.centre /= s.n;
  s.shift = c.opt.area_neutral_placement ? section_restoring_shift(c) : Vec3::Zero();

  // Validity and deltas, as for a single collapse (collapse_evaluate.cpp); the geometric cost's
  // volume terms take each face's swept volume about the kept loop's centroid (the collapse
  // moves no single point).
  StarChange& change = c.change;
  change.clear();
  for (VFace* f : star) {
    const int fidx = c.fi(f);
    const int region = c.face_region[fidx], node = c.region_node[region];
    StarFaceChange fc;
    fc.node = node;
    for (int j = 0; j < 3; ++j) fc.before[j] = to_eigen(f->cP(j)), fc.after[j] = section_position(f->cV(j), s.shift);
    const Vec3 &p0 = fc.before[0], &p1 = fc.before[1], &p2 = fc.before[2];
    const Vec3 &q0 = fc.after[0], &q1 = fc.after[1], &q2 = fc.after[2];
    if (q0 == p0 && q1 == p1 && q2 == p2) continue;  // not moved (a kept loop that does not move)
    const Vec3 n0 = (p1 - p0).cross(p2 - p0), n1 = (q1 - q0).cross(q2 - q0);
    fc.swept_m3 = ((q0 - s.centre).dot((q1 - s.centre).cross(q2 - s.centre)) -
                   (p0 - s.centre).dot((p1 - s.centre).cross(p2 - s.centre))) / 6.0;
    volume_delta_.add(c.face_component[fidx], (q0.dot(q1.cross(q2)) - p0.dot(p1.cross(p2))) / 6.0);
    if (section_removes(f)) {
      fc.removed = true;
      removed_per_node_.add(node, 1.0);
      removed_per_region_.add(region, 1.0);
      area_delta_.add(node, -0.5 * n0.norm());
      change.faces.push_back(fc);
      continue;
    }
    const double n1sq = n1.squaredNorm();
    double steep_m2 = 0;
    if (!c.turn_allowed(n0, n1, steep_m2)) return section_.n = 0, set_refused(CollapseBlock::normal_deviation), false;
    if (steep_m2 > 0) sharp_delta_.add(node, steep_m2);
    area_delta_.add(node, 0.5 * std::sqrt(n1sq) - 0.5 * n0.norm());
    change.faces.push_back(fc);
  }
  if (removed_per_node_.empty() || removed_per_node_.overflow || removed_per_region_.overflow ||
      area_delta_.overflow || volume_delta_.overflow || sharp_delta_.overflow)
    return section_.n = 0, set_refused(CollapseBlock::topology), false;
  _priority = static_cast<ScalarType>(collapse_cost(c, change));
  valid_ = std::isfinite(_priority);
  if (!valid_) section_.n = 0;
  return valid_;
}

// A face between the two loops: two of its corners merge (section_topology_ok checked that
// these are exactly the 2n faces with no corner off the loops).
bool NodeCollapse::section_removes(const VFace* f) const {
  const Section& s = section_;
  int merged[3];
  for (int j = 0; j < 3; ++j) {
    const int g = index_in(s.gone, s.n, f->cV(j));
    merged[j] = g >= 0 ? g : index_in(s.kept, s.n, f->cV(j));
    if (merged[j] < 0) return false;
  }
  return merged[0] == merged[1] || merged[1] == merged[2] || merged[0] == merged[2];
}

void NodeCollapse::execute_section(VMesh& m, Context& c) {
  const Section s = section_;
  std::array<Vec3, kMaxSection> target;
  for (int j = 0; j < s.n; ++j) target[j] = section_position(s.kept[j], s.shift);
  std::vector<int> removed;
  for (int j = 0; j < s.n; ++j) {
    removed.clear();
    for (vcg::face::VFIterator<VFace> it(s.gone[j]); !it.End(); ++it)
      if (it.V1() == s.kept[j] || it.V2() == s.kept[j]) removed.push_back(c.fi(it.F()));
    VPair pair(s.gone[j], s.kept[j]);
    vcg::tri::EdgeCollapser<VMesh, VPair>::Do(m, pair, vcg::Point3d(target[j][0], target[j][1], target[j][2]));
    record_absorbed(c, removed, s.kept[j]);
  }
}

}  // namespace thermodec::collapse
